// A spot light: a point light of intensity I shining into a cone around its axis, full within the inner
// half-angle, none beyond the outer one, smoothstep between (spotFalloff, scene/light.h): E = I x
// falloff / d^2. Power: the cone's share of 4 pi Y(I), 2 pi Y(I) (1 - (cos inner + cos outer) / 2).
#include "lights/kinds.h"

#include <fmt/format.h>
#include <cmath>

namespace symphong {

namespace {

class SpotEmitter final : public Emitter {
public:
    explicit SpotEmitter(const Light& light) : light_(light) {}
    const char* kind() const override { return "spot"; }
    bool isDelta() const override { return true; }
    double power(double) const override { return 2 * kPi * luminance(light_.intensity) * (1 - 0.5 * (light_.cosInner + light_.cosOuter)); }
    bool sample(const Vec3& p, Point2, double pick, EmitterSample& s) const override {
        if (!samplePointSource(light_, p, pick, s)) return false;
        s.radiance *= spotFalloff(dot(-s.wi, light_.direction), light_.cosInner, light_.cosOuter);
        return !isBlack(s.radiance);
    }
    double pdfOfHit(const Vec3&, double, double) const override { return 0.0; }
    std::string describe() const override {
        return fmt::format("position {}, direction {}, intensity {}, cone {:.4g} to {:.4g} degrees", formatTriple(light_.position),
                           formatTriple(light_.direction), formatTriple(light_.intensity), std::acos(light_.cosInner) * 180 / kPi,
                           std::acos(light_.cosOuter) * 180 / kPi);
    }

private:
    Light light_;
};

}  // namespace

std::unique_ptr<Emitter> makeSpotEmitter(const Light& light) { return std::make_unique<SpotEmitter>(light); }

}  // namespace symphong
