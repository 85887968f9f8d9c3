// `symphong --version`: exit 0, the project's version from CMake, and each library's version as its own
// headers give it (a second source: the headers this test was compiled against).
#include <gtest/gtest.h>

#include <OpenEXRConfig.h>
#include <embree3/rtcore_config.h>
#include <png.h>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <string>

namespace {

std::string run(const std::string& command, int& status) {
    std::string out;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return out;
    std::array<char, 4096> buf{};
    while (const std::size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
    status = pclose(pipe);
    return out;
}

}  // namespace

TEST(Version, PrintsTheProgramsAndItsLibrariesVersions) {
    int status = -1;
    const std::string out = run(std::string(SYMPHONG_BINARY) + " --version 2>&1", status);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
    EXPECT_EQ(out.rfind(std::string("symphong ") + SYMPHONG_VERSION + "\n", 0), 0u) << out;
    EXPECT_NE(out.find(std::string("Embree ") + RTC_VERSION_STRING), std::string::npos) << out;
    EXPECT_NE(out.find(std::string("OpenEXR ") + OPENEXR_VERSION_STRING), std::string::npos) << out;
    EXPECT_NE(out.find(std::string("libpng ") + PNG_LIBPNG_VER_STRING), std::string::npos) << out;
    EXPECT_NE(out.find("oneTBB 20"), std::string::npos) << out;
    EXPECT_NE(out.find("Assimp 5."), std::string::npos) << out;
    EXPECT_NE(out.find("MPI: "), std::string::npos) << out;
    EXPECT_EQ(out.find("A subcommand is required"), std::string::npos) << out;
}
