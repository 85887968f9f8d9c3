// compare(): `symphong compare` for files or NumPy arrays, keyword arguments through compareSchema()
// (compare/compare.h); the result is the dict of `symphong compare --json`, with the FLIP map as an array.
#include "compare/compare.h"
#include "compare/image_file.h"
#include "io/input_error.h"
#include "python/common.h"
#include "python/schema_py.h"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>

namespace symphong {

namespace {

/// A path (str or os.PathLike) read as a file, or an array of shape (H, W, 3) / (H, W) taken as linear.
ImageFile imageArgument(const py::handle& value, const char* what, std::string& shownName) {
    if (py::isinstance<py::array>(value)) {
        shownName = fmt::format("<{} array>", what);
        return {fromArray(py::reinterpret_borrow<py::array>(value)), false, "array"};
    }
    if (!py::isinstance<py::str>(value) && !py::hasattr(value, "__fspath__"))
        throw py::type_error(fmt::format("{}: expected a file name or a NumPy array", what));
    shownName = py::str(py::module_::import("os").attr("fspath")(value)).cast<std::string>();
    return readImageFile(shownName);
}

/// regions: "X,Y,W,H;mask.png", or a list of such strings and (x, y, w, h) tuples.
std::string regionsArgument(const py::handle& value) {
    if (value.is_none() || py::isinstance<py::str>(value)) return value.is_none() ? std::string() : value.cast<std::string>();
    std::string out;
    for (const py::handle& item : value) {
        std::string spec;
        if (py::isinstance<py::str>(item)) {
            spec = item.cast<std::string>();
        } else {
            const auto r = item.cast<std::vector<int>>();
            if (r.size() != 4) throw InputError("regions: a rectangle is (x, y, width, height)");
            spec = fmt::format("{},{},{},{}", r[0], r[1], r[2], r[3]);
        }
        out += (out.empty() ? "" : ";") + spec;
    }
    return out;
}

py::object comparePy(const py::object& test, const py::object& reference, const py::kwargs& given) {
    py::dict kwargs = py::dict(given);
    CompareOptions o;
    std::optional<ImageFile> variance;
    if (kwargs.contains("variance")) {
        const py::object v = kwargs["variance"];
        PyDict_DelItemString(kwargs.ptr(), "variance");
        std::string name;
        if (!v.is_none()) variance = imageArgument(v, "variance", name), o.variance = name;
    }
    if (kwargs.contains("regions")) {
        o.regions = regionsArgument(kwargs["regions"]);
        PyDict_DelItemString(kwargs.ptr(), "regions");
    }
    pyschema::applyKwargs(o, compareSchema(), kwargs, "compare");
    const ImageFile t = imageArgument(test, "test", o.test);
    const ImageFile r = imageArgument(reference, "reference", o.reference);
    Comparison c;
    {
        py::gil_scoped_release release;
        c = compareLoaded(t.image, r.image, variance ? &variance->image : nullptr, t.lowDynamicRange && r.lowDynamicRange, o);
    }
    py::dict out = py::module_::import("json").attr("loads")(comparisonJson(c, o).dump());
    if (!c.flip.map.empty()) {
        py::array_t<float> map({c.height, c.width});
        std::copy(c.flip.map.begin(), c.flip.map.end(), map.mutable_data());
        out["flip_values"] = map;
    }
    return out;
}

std::string compareDoc() {
    return "compare(test, reference, " + pyschema::signature(compareSchema()) +
           ")\n\n"
           "`symphong compare`: test against reference, each a file name (.exr, .pfm, .hdr: linear; .png, .jpg: decoded\n"
           "through the sRGB curve) or a NumPy array (H, W, 3) or (H, W) of linear values. variance: the test image's\n"
           "per-pixel variance of the mean (a file or an array, e.g. the third value of render(..., variance=True)).\n"
           "regions: 'X,Y,W,H;mask.png' or a list of strings and (x, y, w, h) tuples.\n"
           "Returns the dict of `symphong compare --json`: 'image' (the whole image) and 'regions' (one dict each) with\n"
           "mse, rmse, relmse, mse_rgb, rmse_rgb, mean_test, mean_reference, mean_ratio, bias, relative_bias,\n"
           "bias_std_error and bias_z (None without variance), flip (None when off); 'flip' (kind, exposures); and\n"
           "'flip_values', the FLIP map as a float32 array (H, W). Bad input raises ValueError (FileNotFoundError for a\n"
           "missing file).\n\n"
           "Keyword arguments (those of `symphong compare`, with the same defaults and checks):\n" +
           pyschema::keywordHelp(compareSchema());
}

}  // namespace

void registerCompare(py::module_& m) {
    static const std::string doc = compareDoc();
    m.def("compare", &comparePy, doc.c_str(), py::arg("test"), py::arg("reference"));
}

}  // namespace symphong
