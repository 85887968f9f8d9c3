// python/host.cpp — what a host application (the Blender add-on, blender/symphong_blender) needs beside
// Scene.from_arrays (python/builder.cpp): principled_to_phong (the loaders' mapping of Blender's Principled
// BSDF, scene/exporter_conventions.h, so that an add-on maps materials exactly as the glTF/FBX readers do),
// render_settings (the render settings' schema as data: names, defaults, ranges, choices, help, so that a
// host's panel has the command line's settings without repeating them) and Progressive (a render taken pass
// by pass, each pass the one-pass image at its count, cancellable from another thread).
#include "estimators/estimator.h"
#include "io/input_error.h"
#include "python/common.h"
#include "python/schema_py.h"
#include "render/renderer.h"
#include "render/settings.h"
#include "scene/exporter_conventions.h"

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>
#include <thread>

namespace symphong {

namespace {

py::object fromJson(const nlohmann::json& j) {
    if (j.is_null()) return py::none();
    if (j.is_boolean()) return py::bool_(j.get<bool>());
    if (j.is_number_unsigned()) return py::int_(j.get<unsigned long long>());
    if (j.is_number_integer()) return py::int_(j.get<long long>());
    if (j.is_number()) return py::float_(j.get<double>());
    if (j.is_string()) return py::str(j.get<std::string>());
    if (j.is_array()) {
        py::list out;
        for (const auto& x : j) out.append(fromJson(x));
        return out;
    }
    py::dict out;
    for (const auto& item : j.items()) out[py::str(item.key())] = fromJson(item.value());
    return out;
}

// ---------------------------------------------------------------------------------------------------
// The render settings' schema as data

py::list renderSettingsList() {
    py::list out;
    const RenderOptions defaults{};
    for (const schema::Field<RenderOptions>& f : renderSchema()) {
        if (!f.in(schema::kPython)) continue;
        py::dict d;
        d["name"] = f.pyKey();
        d["flag"] = f.flag();
        d["help"] = f.help;
        nlohmann::json value = schema::valueOf(f, defaults);
        if (f.negated && value.is_boolean()) value = !value.get<bool>();
        d["default"] = fromJson(value);
        std::string type = "str";
        std::visit(
            [&](const auto& access) {
                using A = std::decay_t<decltype(access)>;
                if constexpr (!std::is_same_v<A, schema::TextAccess<RenderOptions>>) {
                    using T = std::remove_reference_t<typename A::result_type>;
                    if constexpr (std::is_same_v<T, bool>)
                        type = "bool";
                    else if constexpr (std::is_integral_v<T>)
                        type = "int";
                    else if constexpr (std::is_floating_point_v<T>)
                        type = "float";
                    else if constexpr (!std::is_same_v<T, std::string>)
                        type = "list";
                }
            },
            f.access);
        d["type"] = type;
        d["min"] = f.hasRange() && f.lo > -std::numeric_limits<double>::infinity() ? py::object(py::float_(f.lo)) : py::object(py::none());
        d["max"] = f.hasRange() && f.hi < std::numeric_limits<double>::infinity() ? py::object(py::float_(f.hi)) : py::object(py::none());
        d["positive"] = f.positive;
        py::list choices;
        if (f.names)
            for (const std::string& n : f.names()) choices.append(n);
        else if (f.key == "estimator")
            for (const std::string& n : estimatorNames()) choices.append(n);
        else if (f.key == "symmetric_mode")
            for (SymmetricMode mode : {SymmetricMode::Branch, SymmetricMode::Spread}) choices.append(std::string(symmetricModeName(mode)));
        for (int x : f.oneOf) choices.append(x);
        d["choices"] = choices;
        d["changes_pixels"] = f.changesPixels;
        out.append(d);
    }
    return out;
}

// ---------------------------------------------------------------------------------------------------
// A render pass by pass

/// A render of a scene with render()'s keyword arguments, taken to more samples per pixel call by call.
class Progressive {
public:
    Progressive(std::shared_ptr<PyScene> scene, const py::kwargs& given) : scene_(std::move(scene)) {
        py::dict kwargs = py::dict(given);
        pyschema::applyKwargs(options_, renderSchema(), kwargs, "Progressive");
        finishRenderOptions(options_, scene_->scene(), scene_->spec(), pyschema::givenKeys(renderSchema(), kwargs));
        if (options_.progressive())
            throw InputError(
                "Progressive: time, target_error, pass_spp, checkpoint and resume are render()'s; here each advance() is a pass");
        try {
            estimator_ = makeEstimator(options_.estimator, options_.estimatorOptions);
        } catch (const std::invalid_argument& e) {
            throw InputError(fmt::format("estimator: {}", e.what()));
        }
        settings_ = renderSettings(options_);
        state_ = RenderState(settings_.width, settings_.height, settings_.spp);
    }

    /// Takes every tile to min(upTo, spp) samples (GIL released; Ctrl-C or cancel() stop it after the tiles in
    /// flight) and returns the image at that count.
    py::array_t<float> advance(std::uint32_t upTo) {
        upTo = std::min(upTo, settings_.spp);
        cancel_.store(false);
        if (upTo > state_.samplesReached()) {
            runInterruptible([&](const std::atomic<bool>& interrupt) {
                RenderSettings s = settings_;
                std::atomic<bool> either{false};
                s.cancel = &either;
                // Either Ctrl-C (interrupt) or cancel() from another thread stops the pass: a watcher joins them.
                std::atomic<bool> done{false};
                std::thread watch([&] {
                    while (!done.load()) {
                        if (interrupt.load() || cancel_.load()) either.store(true);
                        std::this_thread::sleep_for(std::chrono::milliseconds(5));
                    }
                });
                try {
                    // One tracer for every advance (render/renderer.h makeTracer: making one goes over every
                    // triangle, 0.2 s on a 2M-triangle mesh, which each call paid).
                    if (!tracer_) tracer_ = makeTracer(scene_->scene(), scene_->accel(), *estimator_, s, state_);
                    renderSamples(*tracer_, *estimator_, s, state_, upTo, &progress_);
                } catch (...) {
                    done.store(true);
                    watch.join();
                    throw;
                }
                done.store(true);
                watch.join();
                return 0;
            });
        }
        return toArray(state_.image());
    }

    void cancel() { cancel_.store(true); }
    std::uint32_t samplesReached() const { return state_.samplesReached(); }
    std::uint32_t spp() const { return settings_.spp; }
    int width() const { return settings_.width; }
    int height() const { return settings_.height; }
    std::uint64_t samplesDone() const { return progress_.load(); }
    py::dict stats() const {
        py::dict d;
        d["seconds"] = state_.seconds;
        d["cpu_seconds"] = state_.cpuSeconds;
        d["rays"] = state_.rays;
        d["samples"] = state_.samples;
        d["paths"] = state_.paths;
        d["bad_samples"] = state_.badSamples;
        d["spp_reached"] = state_.samplesReached();
        d["estimator"] = estimator_->name();
        d["sampler"] = effectiveSampler(*estimator_, settings_.sampler);
        d["splitting"] = options_.splitting;  // the one used: auto resolved
        return d;
    }

private:
    std::shared_ptr<PyScene> scene_;
    RenderOptions options_;
    RenderSettings settings_;
    std::unique_ptr<Estimator> estimator_;
    RenderState state_;
    std::unique_ptr<PathTracer> tracer_;  ///< for state_, made at the first advance
    std::atomic<bool> cancel_{false};
    std::atomic<std::uint64_t> progress_{0};
};

}  // namespace

void registerHost(py::module_& m) {
    m.def(
        "principled_to_phong",
        [](const py::object& baseColor, double metallic, double specular, double roughness) {
            Color rhoD, rhoS;
            double n = 0;
            const auto rgb = baseColor.cast<std::vector<double>>();
            if (rgb.size() != 3 && rgb.size() != 4)
                throw InputError(fmt::format("base_color: expected 3 numbers (RGB), got {}", rgb.size()));
            const Color base(rgb[0], rgb[1], rgb[2]);
            if (!isFinite(base) || minComponent(base) < 0) throw InputError("base_color: every value must be finite and >= 0");
            for (const auto& [v, name] : {std::pair{metallic, "metallic"}, {specular, "specular"}, {roughness, "roughness"}})
                if (!std::isfinite(v)) throw InputError(fmt::format("{} = {} is not finite", name, v));
            blenderPrincipledToPhong(base, metallic, specular, roughness, rhoD, rhoS, n);
            py::dict d;
            d["rho_d"] = py::make_tuple(rhoD.x, rhoD.y, rhoD.z);
            d["rho_s"] = py::make_tuple(rhoS.x, rhoS.y, rhoS.z);
            d["n"] = n;
            return d;
        },
        py::arg("base_color"), py::arg("metallic") = 0.0, py::arg("specular") = 0.5, py::arg("roughness") = 0.5,
        R"(principled_to_phong(base_color, metallic=0, specular=0.5, roughness=0.5) -> dict(rho_d, rho_s, n)

Blender's Principled BSDF as a Phong material, as the glTF, FBX and OBJ readers map the files Blender writes
(docs/scene-format.md): F0 = 0.08 x specular, rho_s = F0 (1 - metallic) + base x metallic,
rho_d = base (1 - metallic) (1 - F0), n = 2 / alpha^2 - 2 with alpha = roughness^2 (at most 10^4). The same
C++ function the readers call; Scene.from_arrays applies it to a material given by these keys.)");
    m.def("render_settings", &renderSettingsList,
          R"(render_settings() -> list of dicts, one per keyword of render(), in the order of `symphong render --help`:
name (the keyword), flag (the command-line option), help, default, type ('int', 'float', 'bool', 'str', 'list'),
min and max (the range, or None), positive, choices (the valid names or values, or empty) and changes_pixels.
The settings' schema itself (src/render/settings.cpp), so a front end's panel has the command line's names,
defaults and ranges.)");

    py::class_<Progressive>(m, "Progressive", R"(Progressive(scene, **render_keywords): a render taken pass by pass.

advance(spp) takes every pixel to spp samples (at most the render's spp) and returns the image at that count:
bit for bit the image render() gives with that many samples of the same render (each pass continues the
samples of the one before). The GIL is released meanwhile; Ctrl-C, or cancel() from another thread, stops a
pass after the tiles in flight (the image then mixes counts: samples_reached says the least).
Keywords are render()'s, without time, target_error, pass_spp, checkpoint and resume.)")
        .def(py::init([](const py::object& scene, const py::kwargs& kwargs) {
                 return std::make_unique<Progressive>(sceneArgument(scene), kwargs);
             }),
             py::arg("scene"))
        .def("advance", &Progressive::advance, py::arg("spp"),
             "advance(spp) -> (H, W, 3) float32 image with every pixel at min(spp, self.spp) samples")
        .def("cancel", &Progressive::cancel, "Stops the pass in progress after the tiles in flight (thread-safe).")
        .def_property_readonly("samples_reached", &Progressive::samplesReached, "samples per pixel every pixel has")
        .def_property_readonly("samples_done", &Progressive::samplesDone, "camera samples taken so far (for a progress bar)")
        .def_property_readonly("spp", &Progressive::spp)
        .def_property_readonly("width", &Progressive::width)
        .def_property_readonly("height", &Progressive::height)
        .def("stats", &Progressive::stats,
             "dict: seconds, cpu_seconds, rays, samples, paths, bad_samples, spp_reached, estimator, sampler");
}

}  // namespace symphong
