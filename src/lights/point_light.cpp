// A point light of radiant intensity I: from a point at distance d it arrives as E = I / d^2 on a
// surface facing it, along the one direction towards it (a delta emitter). Power 4 pi Y(I).
#include "lights/kinds.h"

#include <fmt/format.h>
#include <cmath>

namespace symphong {

namespace {

class PointEmitter final : public Emitter {
public:
    explicit PointEmitter(const Light& light) : light_(light) {}
    const char* kind() const override { return "point"; }
    bool isDelta() const override { return true; }
    double power(double) const override { return 4 * kPi * luminance(light_.intensity); }
    bool sample(const Vec3& p, Point2, double pick, EmitterSample& s) const override {
        return samplePointSource(light_, p, pick, s) && !isBlack(s.radiance);
    }
    double pdfOfHit(const Vec3&, double, double) const override { return 0.0; }
    std::string describe() const override {
        return fmt::format("position {}, intensity {}", formatTriple(light_.position), formatTriple(light_.intensity));
    }

private:
    Light light_;
};

}  // namespace

bool samplePointSource(const Light& light, const Vec3& p, double pick, EmitterSample& s) {
    const Vec3 toLight = light.position - p;
    const double dist2 = dot(toLight, toLight);
    if (!(dist2 > 0)) return false;
    s.wi = toLight / std::sqrt(dist2);
    s.radiance = light.intensity / dist2;
    s.pdf = pick;
    s.target = light.position;
    s.toInfinity = false;
    return true;
}

std::unique_ptr<Emitter> makePointEmitter(const Light& light) { return std::make_unique<PointEmitter>(light); }

std::string formatTriple(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x, v.y, v.z); }

}  // namespace symphong
