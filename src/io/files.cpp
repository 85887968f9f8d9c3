#include "io/files.h"

#include "io/input_error.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <unistd.h>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace symphong {

namespace fs = std::filesystem;

std::string lowerExtension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return ext;
}

std::string readTextFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw MissingFileError(fmt::format("{}: no such file", path));
    if (std::filesystem::is_directory(path, ec)) throw InputError(fmt::format("{}: is a directory, not a file", path));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw InputError(fmt::format("{}: read error", path));
    return ss.str();
}

std::string temporaryPathFor(const std::string& path) {
    const std::filesystem::path p(path);
    return (p.parent_path() / fmt::format(".{}.tmp-{}", p.filename().string(), ::getpid())).string();
}

void checkCanCreate(const std::string& path) {
    const fs::path p(path);
    std::error_code ec;
    if (fs::is_directory(p, ec)) throw InputError(fmt::format("{}: is a directory", path));
    if (!p.parent_path().empty() && !fs::exists(p.parent_path(), ec)) {
        fs::create_directories(p.parent_path(), ec);
        if (ec) throw InputError(fmt::format("{}: cannot create directory {}: {}", path, p.parent_path().string(), ec.message()));
    }
    const std::string tmp = temporaryPathFor(path);
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw InputError(fmt::format("{}: cannot create a file in {}", path, p.parent_path().empty() ? "." : p.parent_path().string()));
    std::fclose(f);
    fs::remove(tmp, ec);
}

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    const std::string tmp = temporaryPathFor(path);
    try {
        write(tmp);
        std::filesystem::rename(tmp, path);
    } catch (const std::exception& e) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw InputError(fmt::format("{}: cannot write: {}", path, e.what()));
    }
}

namespace {

/// fsync of a file or directory; throws std::runtime_error naming what failed.
void syncToDisk(const std::string& path, bool directory) {
    const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
    if (fd < 0) throw std::runtime_error(fmt::format("cannot open {} to flush it: {}", path, std::strerror(errno)));
    const int rc = ::fsync(fd);
    const int err = errno;
    ::close(fd);
    if (rc != 0) throw std::runtime_error(fmt::format("cannot flush {} to the disk: {}", path, std::strerror(err)));
}

}  // namespace

void writeDurably(const std::string& path, const std::function<void(const std::string&)>& write) {
    writeAtomically(path, [&](const std::string& tmp) {
        write(tmp);
        syncToDisk(tmp, false);
    });
    const std::string dir = fs::path(path).parent_path().string();
    try {
        syncToDisk(dir.empty() ? "." : dir, true);
    } catch (const std::exception& e) {
        throw InputError(fmt::format("{}: {}", path, e.what()));
    }
}

void writeFile(const std::string& path, const std::string& bytes) {
    writeAtomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out << bytes;
        out.close();
        if (!out) throw std::runtime_error("write failed");
    });
}

}  // namespace symphong
