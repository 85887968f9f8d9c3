// fuzz/tinyobj_instrumented.cpp — tinyobjloader's implementation (Debian's libtinyobjloader-dev header,
// the same version as the shared library symphong_lib links) compiled into fuzz_obj and fuzz_json
// with the fuzzer's coverage and sanitizer instrumentation. Definitions in the executable take
// precedence over those of libtinyobjloader.so, so the OBJ/MTL parser the fuzzer drives is this one:
// libFuzzer sees its branches and AddressSanitizer its memory accesses.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
