#include "cli/cli.h"
#include "distrib/mpi_job.h"

int main(int argc, char** argv) {
    const symphong::MpiJob job(&argc, &argv);  // MPI only when started by mpirun/mpiexec/srun
    return symphong::runCli(argc, argv, job);
}
