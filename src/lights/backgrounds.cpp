// What rays that leave the scene see: an HDR environment map (importance-sampled by luminance x
// sin(theta), density pick x p_map(wi) in solid angle; power pi r^2 x integral Y(L) dw over the scene's
// bounding sphere), the default sky or a constant radiance (neither is light-sampled: power 0).
#include "lights/kinds.h"

#include <fmt/format.h>

namespace symphong {

namespace {

class EnvironmentMapEmitter final : public Emitter {
public:
    explicit EnvironmentMapEmitter(const EnvironmentMap& map) : map_(map) {}
    const char* kind() const override { return "environment"; }
    bool isBackground() const override { return true; }
    double power(double sceneRadius) const override { return kPi * sceneRadius * sceneRadius * map_.luminanceIntegral(); }
    bool sample(const Vec3&, Point2 u, double pick, EmitterSample& s) const override {
        double pdf = 0;
        s.wi = map_.sample(u, pdf);
        if (!(pdf > 0)) return false;
        s.pdf = pick * pdf;
        s.radianceLater = true;
        s.toInfinity = true;
        return true;
    }
    double pdfOfHit(const Vec3& d, double, double pick) const override { return pick * map_.pdf(d); }
    Color backgroundRadiance(const Vec3& d) const override { return map_.radiance(d); }
    Color backgroundRadianceAndPdf(const Vec3& d, double pick, double& pdf) const override {
        const Color L = map_.radianceAndPdf(d, pdf);
        pdf *= pick;
        return L;
    }
    std::string describe() const override {
        return fmt::format("HDR map {} ({} x {}), scale {:.6g}, rotation {:.4g} degrees, {} filtering; integral of Y(L) dw = {:.6g}",
                           map_.image().name(), map_.image().width(), map_.image().height(), map_.scale(), map_.rotationDegrees(),
                           filterName(map_.filter()), map_.luminanceIntegral());
    }

private:
    const EnvironmentMap& map_;
};

class SkyEmitter final : public Emitter {
public:
    explicit SkyEmitter(const Sky& sky) : sky_(sky) {}
    const char* kind() const override { return "environment"; }
    bool isBackground() const override { return true; }
    double power(double) const override { return 0.0; }
    bool sample(const Vec3&, Point2, double, EmitterSample&) const override { return false; }
    double pdfOfHit(const Vec3&, double, double) const override { return 0.0; }
    Color backgroundRadiance(const Vec3& d) const override { return skyRadiance(sky_, d); }
    std::string describe() const override {
        return fmt::format("default sky: zenith {}, horizon {}, ground {}", formatTriple(sky_.zenith), formatTriple(sky_.horizon),
                           formatTriple(sky_.ground));
    }

private:
    Sky sky_;
};

class ConstantEnvironmentEmitter final : public Emitter {
public:
    explicit ConstantEnvironmentEmitter(const Color& radiance) : radiance_(radiance) {}
    const char* kind() const override { return "environment"; }
    bool isBackground() const override { return true; }
    double power(double) const override { return 0.0; }
    bool sample(const Vec3&, Point2, double, EmitterSample&) const override { return false; }
    double pdfOfHit(const Vec3&, double, double) const override { return 0.0; }
    Color backgroundRadiance(const Vec3&) const override { return radiance_; }
    std::string describe() const override { return "constant radiance " + formatTriple(radiance_); }

private:
    Color radiance_;
};

}  // namespace

std::unique_ptr<Emitter> makeBackgroundEmitter(const Scene& scene) {
    if (scene.environmentMap) return std::make_unique<EnvironmentMapEmitter>(*scene.environmentMap);
    if (scene.sky) return std::make_unique<SkyEmitter>(*scene.sky);
    return std::make_unique<ConstantEnvironmentEmitter>(scene.environment);
}

}  // namespace symphong
