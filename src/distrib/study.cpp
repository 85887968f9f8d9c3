#include "distrib/study.h"

#include "distrib/render.h"
#include "io/input_error.h"

#include <mpi.h>

#include <fmt/format.h>

#include <cstdio>

namespace symphong {

namespace {

class MpiStudyRuntime : public StudyRuntime {
public:
    explicit MpiStudyRuntime(const MpiJob& job) : job_(job) {}
    RenderResult render(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                        std::atomic<std::uint64_t>* progress) const override {
        return renderDistributed(job_, scene, accel, estimator, settings, progress);
    }
    std::string agreeOnError(const std::string& localError) const override {
        std::string error = job_.firstError(localError);
        agreed_ = !error.empty();
        return error;
    }
    bool writersValue(bool value) const override {
        int v = value ? 1 : 0;
        MPI_Bcast(&v, 1, MPI_INT, 0, MPI_COMM_WORLD);
        return v != 0;
    }
    int writersInt(int value) const override {
        MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
        return value;
    }
    std::vector<int> writersInts(std::vector<int> values) const override {
        int n = writersInt(static_cast<int>(values.size()));
        values.resize(static_cast<std::size_t>(n));
        if (n > 0) MPI_Bcast(values.data(), n, MPI_INT, 0, MPI_COMM_WORLD);
        return values;
    }
    bool writer() const override { return job_.root(); }
    int processes() const override { return job_.size(); }
    StopReason renderPasses(const Scene& scene, const Accel& accel, const Estimator& estimator, const RenderSettings& settings,
                            const StopRules& rules, RenderState& state, const std::function<void(const PassReport&)>& afterPass,
                            std::atomic<std::uint64_t>* progress) const override {
        if (!job_.root()) {
            followPasses(job_, scene, accel, estimator, settings);
            return StopReason::Spp;  // rank 0 knows; the study asks it (writersValue)
        }
        const StopReason why = renderProgressive(scene, accel, estimator, settings, rules, state, afterPass, progress,
                                                 leadPasses(job_, scene, accel, estimator, settings, progress));
        endPasses(job_);
        return why;
    }
    bool errorAgreed() const { return agreed_; }

private:
    const MpiJob& job_;
    mutable bool agreed_ = false;
};

}  // namespace

StudyOutcome runStudyDistributed(const MpiJob& job, const StudyConfig& config, const std::atomic<bool>* cancel, bool showProgress) {
    if (!job.active() || job.size() == 1) return runStudy(config, cancel, showProgress);
    const MpiStudyRuntime runtime(job);
    // Only rank 0 acts on an interruption; the others follow it at the next render.
    try {
        return runStudy(config, job.root() ? cancel : nullptr, showProgress && job.root(), &runtime);
    } catch (const InputError& e) {
        if (runtime.errorAgreed()) throw;  // every rank throws it; rank 0 reports it
        fmt::print(stderr, "symphong: error: rank {}: {}\n", job.rank(), e.what());
        std::fflush(stderr);
        job.abort(2);
    }
}

}  // namespace symphong
