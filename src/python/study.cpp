// furnace() and study(): keyword arguments through furnaceSchema() and studySchema() (study/config.h),
// run with the GIL released, results as the JSON the command line writes.
#include "io/files.h"
#include "io/input_error.h"
#include "python/common.h"
#include "python/schema_py.h"
#include "render/progress.h"
#include "study/config.h"
#include "study/environment.h"

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <filesystem>

namespace symphong {

namespace {

py::object jsonLoads(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

py::object furnacePy(const py::kwargs& kwargs) {
    FurnaceOptions o;
    pyschema::applyKwargs(o, furnaceSchema(), kwargs, "furnace");
    const FurnaceTable t = toFurnaceTable(o, false);
    const auto rows = runInterruptible([&](const std::atomic<bool>& cancel) { return runFurnaceTable(t, {}, &cancel); });
    return jsonLoads(furnaceJson(rows));
}

py::tuple studyPy(const py::object& scene, const py::kwargs& given) {
    py::dict kwargs = py::dict(given);
    const bool showProgress = takeProgress(kwargs);
    StudyOptions o;
    if (py::isinstance<PyScene>(scene))
        o.config.scene = scene.cast<const PyScene&>().spec();
    else if (py::isinstance<py::str>(scene))
        o.config.scene = scene.cast<std::string>();
    else
        throw py::type_error("scene: expected a symphong.Scene or a spec string");
    pyschema::applyKwargs(o, studySchema(), kwargs, "study");
    const StudyConfig c = toStudyConfig(o, false);
    const StudyOutcome outcome = runInterruptible([&](const std::atomic<bool>& cancel) { return runStudy(c, &cancel, showProgress); });
    if (c.plots && !outcome.plotted)
        throw std::runtime_error("the study's plots could not be made (needs python3 with matplotlib); pass plots=False to skip them");
    const std::filesystem::path dir(c.outDir);
    py::object results = jsonLoads(readTextFile((dir / "results.json").string()));
    return py::make_tuple(results["rows"], (dir / "report.md").string());
}

std::string furnaceDoc() {
    return "furnace(" + pyschema::signature(furnaceSchema()) +
           ")\n\n"
           "The single-point furnace of `symphong furnace`: each estimator evaluated `repeats` times at one shading\n"
           "point (grey Phong material rho_d, rho_s, exponent n, view angle theta from the normal, azimuth phi) under an\n"
           "environment whose reflected radiance is known exactly.\n\n"
           "estimators, environments: 'all', 'a,b' or a list of names (environments: constant, gradient, disk, band,\n"
           "halfspace). n, theta: a number or a list; grid=True runs n in {1,10,100,1000,10000} x theta in {0,30,60,85}.\n"
           "Returns a list of dicts, one per environment x n x theta x estimator, in that order, with the keys and\n"
           "values of `symphong furnace --json` (estimate, std_error, exact, relative_bias, z, variance,\n"
           "directions_per_estimate, variance_times_directions, seconds_per_estimate, efficiency, ...). The same\n"
           "arguments give the same rows as the command line, timings aside.\n\n"
           "Keyword arguments (those of `symphong furnace`, with the same defaults and checks):\n" +
           pyschema::keywordHelp(furnaceSchema());
}

std::string studyDoc() {
    return "study(scene='cornell', " + pyschema::signature(studySchema()) +
           ", progress=None)\n\n"
           "Runs `symphong study`: renders `scene` (a Scene or a spec string) with each estimator under each sampler\n"
           "(the set estimators in each of symmetric_modes), at each spp, `repeats` independent times, against a\n"
           "reference (rendered at reference_spp and cached in `out`, or the EXR file `reference`), and writes\n"
           "results.csv, results.json, plots, heat maps, crops and report.md into `out`.\n\n"
           "Returns (rows, report_path): rows is the list of dicts of results.json's \"rows\" (one per estimator x spp x\n"
           "repeat). Lists may be given as 'a,b' strings or Python lists. Ctrl-C raises KeyboardInterrupt and keeps the\n"
           "finished rows in out/results.csv. plots=False skips matplotlib; python names the interpreter for the plots.\n\n"
           "Keyword arguments (those of `symphong study`, with the same defaults and checks):\n" +
           pyschema::keywordHelp(studySchema());
}

}  // namespace

void registerStudy(py::module_& m) {
    static const std::string furnace = furnaceDoc(), study = studyDoc();
    m.def("furnace", &furnacePy, furnace.c_str());
    m.def("study", &studyPy, study.c_str(), py::arg("scene") = "cornell");
    m.def(
        "environments", [] { return environmentNames(); }, "The furnace's environment names.");
}

}  // namespace symphong
