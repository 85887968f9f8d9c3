#include "cli/cli.h"

int main(int argc, char** argv) { return symphong::runCli(argc, argv); }
