#include "distrib/mpi_job.h"

#include <mpi.h>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace symphong {

bool MpiJob::launchedByMpi() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
        if (std::getenv(name)) return true;
    return false;
}

MpiJob::MpiJob(int* argc, char*** argv) {
    if (!launchedByMpi()) return;
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_MULTIPLE, &provided) != MPI_SUCCESS) throw std::runtime_error("MPI_Init_thread failed");
    active_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    if (provided < MPI_THREAD_MULTIPLE && size_ > 1) {
        if (rank_ == 0) std::fputs("symphong: error: this MPI library does not support MPI_THREAD_MULTIPLE\n", stderr);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
}

MpiJob::~MpiJob() {
    if (!active_) return;
#if defined(__SANITIZE_ADDRESS__)
    // LeakSanitizer's end-of-process check, run now, while Open MPI is still initialised: its own
    // allocations are still reachable from its components, which MPI_Finalize unloads (their memory
    // would then look leaked, from code that no longer has a name). Our objects are all gone by now
    // (runCli has returned), so a leak of ours is still reported. The check runs once; none at exit.
    __lsan_do_leak_check();
#endif
    MPI_Finalize();
}

std::string MpiJob::firstError(const std::string& localError) const {
    if (!active_ || size_ == 1) return localError;
    const int mine = localError.empty() ? size_ : rank_;
    int first = size_;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == size_) return {};
    int length = rank_ == first ? static_cast<int>(localError.size()) : 0;
    MPI_Bcast(&length, 1, MPI_INT, first, MPI_COMM_WORLD);
    std::string message = rank_ == first ? localError : std::string(static_cast<std::size_t>(length), ' ');
    MPI_Bcast(message.data(), length, MPI_CHAR, first, MPI_COMM_WORLD);
    return first == 0 ? message : "rank " + std::to_string(first) + ": " + message;
}

void MpiJob::abort(int code) const {
    if (active_) MPI_Abort(MPI_COMM_WORLD, code);
    std::exit(code);
}

std::string mpiVersion() {
    char text[MPI_MAX_LIBRARY_VERSION_STRING];
    int length = 0;
    MPI_Get_library_version(text, &length);  // allowed before MPI_Init
    const std::string all(text, static_cast<std::size_t>(std::max(0, length)));
    return all.substr(0, all.find_first_of(",\n"));
}

}  // namespace symphong
