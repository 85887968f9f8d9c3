// A directional light (the sun): irradiance E on a surface facing it, arriving along -direction from
// infinitely far (a delta emitter; its shadow ray goes to infinity). Power: E over the disc the scene's
// bounding sphere shows it, pi r^2 Y(E).
#include "lights/kinds.h"

#include <fmt/format.h>

namespace symphong {

namespace {

class DirectionalEmitter final : public Emitter {
public:
    explicit DirectionalEmitter(const Light& light) : light_(light) {}
    const char* kind() const override { return "directional"; }
    bool isDelta() const override { return true; }
    double power(double sceneRadius) const override { return kPi * sceneRadius * sceneRadius * luminance(light_.intensity); }
    bool sample(const Vec3&, Point2, double pick, EmitterSample& s) const override {
        s.wi = -light_.direction;
        s.radiance = light_.intensity;
        s.pdf = pick;
        s.toInfinity = true;
        return !isBlack(s.radiance);
    }
    double pdfOfHit(const Vec3&, double, double) const override { return 0.0; }
    std::string describe() const override {
        return fmt::format("direction {}, irradiance {}", formatTriple(light_.direction), formatTriple(light_.intensity));
    }

private:
    Light light_;
};

}  // namespace

std::unique_ptr<Emitter> makeDirectionalEmitter(const Light& light) { return std::make_unique<DirectionalEmitter>(light); }

}  // namespace symphong
