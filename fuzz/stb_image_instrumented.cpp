// fuzz/stb_image_instrumented.cpp — stb_image's implementation (Debian's libstb-dev header, the source
// of the libstb.so that symphong_lib links) compiled into fuzz_texture with the fuzzer's coverage and
// sanitizer instrumentation, with stb's default format set as Debian builds it. Definitions in the
// executable take precedence over those of libstb.so, so the decoder the fuzzer drives is this one:
// libFuzzer sees its branches and AddressSanitizer its memory accesses.
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
