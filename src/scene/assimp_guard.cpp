// Assimp's importers run first in a child process: Assimp 5.2 itself crashes (null reads, unbounded
// recursion) or grows without bound on some malformed Collada and FBX files (tests/data/fuzz/third-party),
// which no check of ours before it can prevent. The child reads the file with the same importer and flags,
// under a limit on its address space, and only tells how it went: when it crashed, ran out of memory or
// Assimp refused the file (its message comes back through a pipe) the load is an InputError naming the
// file; when it read it, the parent reads the file itself (the same code on the same bytes: it cannot
// crash where the child did not). The cost is a second parse of every file that loads (docs/performance.md).
// SYMPHONG_ASSIMP_IN_PROCESS=1 skips the child (the fuzzers want Assimp's crashes in their own process).
// The child is a fork() without exec: safe where every lock the child takes survives the fork, as glibc's
// allocator's do. GCC 12's AddressSanitizer allocator does not hold its locks across fork(), so a child
// forked while another thread allocates waits forever on its first allocation (a Python test of the
// sanitizer build hung so, its child stopped in ASan's SizeClassAllocator64 mutex, on 2026-12-06): in an
// ASan build the file is read in the process when the process has other threads.
#include "scene/assimp_guard.h"

#include "io/input_error.h"
#include "io/memory.h"
#include "scene/scene.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <assimp/Importer.hpp>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>

namespace symphong {

namespace {

// How the child ends.
constexpr int kRead = 0, kAssimpRefused = 3, kOutOfMemory = 4, kOtherException = 5;

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;  // its shadow memory needs terabytes of address space: no limit then
#else
constexpr bool kAddressSanitizer = false;
#endif

/// The child: Assimp's error message (when it refuses the file) goes to `fd`, the outcome to the exit code.
[[noreturn]] void childRead(const std::string& path, std::uint64_t limit, int fd) {
    if (!kAddressSanitizer) {
        const rlimit r{static_cast<rlim_t>(limit), static_cast<rlim_t>(limit)};
        setrlimit(RLIMIT_AS, &r);
    }
    const int devNull = open("/dev/null", O_WRONLY);  // a sanitizer's report of a crash in Assimp is not ours to print
    if (devNull >= 0) dup2(devNull, STDERR_FILENO);
    int code = kRead;
    try {
        Assimp::Importer importer;
        if (!importWithAssimp(importer, path)) {
            code = kAssimpRefused;
            const std::string message = importer.GetErrorString();
            for (std::size_t done = 0; done < message.size();) {
                const ssize_t n = write(fd, message.data() + done, message.size() - done);
                if (n <= 0) break;
                done += static_cast<std::size_t>(n);
            }
        }
    } catch (const std::bad_alloc&) {
        code = kOutOfMemory;
    } catch (...) {
        code = kOtherException;
    }
    _exit(code);  // no destructors of the parent's objects, no atexit handlers, no buffers flushed twice
}

std::string readAll(int fd) {
    std::string out;
    char buffer[4096];
    for (;;) {
        const ssize_t n = read(fd, buffer, sizeof buffer);
        if (n > 0) out.append(buffer, static_cast<std::size_t>(n));
        else if (n == 0 || errno != EINTR) break;
    }
    return out;
}

}  // namespace

std::uint64_t assimpChildMemoryLimit(std::uint64_t fileBytes) {
    // Room for the program itself and a generous multiple of the file: normal files need a few tens of
    // times their size; the malformed ones of tests/data/fuzz/third-party ask for gigabytes from kilobytes.
    const std::uint64_t wanted = std::max<std::uint64_t>(std::uint64_t{2} << 30, saturatingMultiply(fileBytes, 200));
    return std::min(wanted, memoryBudgetBytes());
}

const aiScene* importWithAssimp(Assimp::Importer& importer, const std::string& path) {
    const aiScene* ai = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_JoinIdenticalVertices |
                                                    aiProcess_ValidateDataStructure);
    return ai && ai->mRootNode && !(ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE) ? ai : nullptr;
}

/// The threads of this process (Linux: the entries of /proc/self/task); 0 when it cannot tell.
[[maybe_unused]] static std::size_t processThreads() {
    std::error_code ec;
    std::size_t n = 0;
    for (std::filesystem::directory_iterator it("/proc/self/task", ec), end; !ec && it != end; it.increment(ec)) ++n;
    return ec ? 0 : n;
}

void checkAssimpInChild(const std::string& path) {
    if (const char* env = std::getenv("SYMPHONG_ASSIMP_IN_PROCESS"); env && std::string(env) == "1") return;
#if defined(__SANITIZE_ADDRESS__)
    if (processThreads() != 1) return;  // see the top of the file: ASan's allocator and fork()
#endif
    std::error_code ec;
    const std::uint64_t limit = assimpChildMemoryLimit(std::filesystem::file_size(path, ec));
    int fds[2];
    if (pipe(fds) != 0) return;  // no child to be had: read it here, as before
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]), close(fds[1]);
        return;
    }
    if (pid == 0) {
        close(fds[0]);
        childRead(path, limit, fds[1]);
    }
    close(fds[1]);
    const std::string message = readAll(fds[0]);
    close(fds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code == kRead || code == kOtherException) return;  // read (or an exception the parent's read reports)
    if (code == kAssimpRefused)  // refused with a message: the parent need not read it (it may be huge)
        throw InputError(fmt::format("{}: cannot read it (Assimp: {})", path, message));
    if (code == kOutOfMemory)
        throw InputError(fmt::format("{}: Assimp {} ran out of memory reading it (limit {:.1f} GiB for a file of this size): the file is "
                                     "malformed, or too large for this machine",
                                     path, assimpVersion(), static_cast<double>(limit) / (1 << 30)));
    throw InputError(fmt::format("{}: Assimp {} crashed reading it ({}): the file is malformed, or uses something Assimp cannot read",
                                 path, assimpVersion(),
                                 WIFSIGNALED(status) ? std::string(strsignal(WTERMSIG(status)))
                                                     : fmt::format("its process ended with status {}", code)));
}

}  // namespace symphong
