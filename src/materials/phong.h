// materials/ — surface reflectance. Owns the normalised modified Phong BRDF (Lafortune and Willems
// 1994; the paper's erratum 1), its exact directional albedo, and the rules that keep a material
// physically plausible. Everything is expressed in the local shading frame where the normal is +Z.
#pragma once

#include "math/vec3.h"

#include <array>
#include <cstdint>
#include <string>

namespace symphong {

/// A texture on one parameter of a material: an index into the scene's texture table (scene/), and the
/// affine map of texture coordinates u' = a u + b v + c, v' = d u + e v + f, stored {a, b, c, d, e, f}:
/// the MTL options -s and -o (a, e the scale, c, f the offset), or glTF's KHR_texture_transform (offset,
/// rotation, scale) turned into symphong's v-up coordinates.
struct TextureRef {
    std::int32_t index = -1;  ///< -1: no texture
    std::array<double, 6> transform{1, 0, 0, 0, 1, 0};
    bool present() const { return index >= 0; }
    double u(double s, double t) const { return transform[0] * s + transform[1] * t + transform[2]; }
    double v(double s, double t) const { return transform[3] * s + transform[4] * t + transform[5]; }
};

/// How textures set a material's parameters at a point. materials/ only records them; scene/surface.h
/// looks them up and turns them into Phong parameters.
struct MaterialTextures {
    enum class Model {
        Phong,              ///< rho_d = Kd x diffuse, rho_s = Ks x specular, n = Ns x exponent (its first channel)
        MetallicRoughness,  ///< glTF: base colour = baseColor x diffuse, roughness = roughness x G and metallic =
                            ///< metallic x B of metallicRoughness, then the Phong approximation of scene/assimp_loader
    };
    Model model = Model::Phong;
    TextureRef diffuse, specular, exponent, metallicRoughness;
    TextureRef emission;   ///< Le = Ke x emission
    TextureRef alpha;      ///< cut-out: where its coverage is below 1/2 the surface is a hole
    /// Tangent-space normal map (OpenGL convention: red along the tangent, the direction of increasing u;
    /// green along the bitangent, increasing v; blue along the normal): n = normalize((2c - 1) x (s, s, 1))
    /// with s = normalScale (glTF's normalTexture.scale, MTL's -bm). scene/shading_normal.h applies it.
    TextureRef normal;
    double normalScale = 1;
    /// Height (bump) map: the surface displaced along its normal by bumpScale x the map's first channel
    /// (MTL's -bm, in scene units), its normal by finite differences of that height.
    TextureRef bump;
    double bumpScale = 1;
    Color baseColor{1.0};  ///< MetallicRoughness factors
    double metallic = 0, roughness = 1;
    Color specularF0{0.04};  ///< MetallicRoughness: a dielectric's reflectance at normal incidence (KHR_materials_specular, _ior)

    bool any() const {
        return diffuse.present() || specular.present() || exponent.present() || metallicRoughness.present() || emission.present() ||
               alpha.present() || perturbsNormal();
    }
    /// Whether a normal or bump map changes the shading normal.
    bool perturbsNormal() const { return normal.present() || bump.present(); }
    /// Whether the textures change rho_d, rho_s or n (not only emission or coverage).
    bool reflectance() const { return diffuse.present() || specular.present() || exponent.present() || metallicRoughness.present(); }
};

struct PhongMaterial {
    std::string name = "default";
    Color rhoD{0.7};            ///< diffuse albedo rho_d (the reflected fraction of the diffuse lobe)
    Color rhoS{0.0};            ///< specular albedo rho_s (at normal incidence, before the horizon cuts the lobe)
    double exponent = 1;        ///< Phong exponent n >= 0
    Color emission{0.0};        ///< emitted radiance Le on the front side (counter-clockwise winding)
    MaterialTextures textures;  ///< texture maps on these parameters (none by default)

    bool isEmissive() const { return !isBlack(emission); }
    bool hasSpecular() const { return !isBlack(rhoS); }
};

/// Normalised modified Phong BRDF, wo and wi in the local frame (normal +Z):
///   f(wo, wi) = rho_d / pi + rho_s (n+2)/(2 pi) cos^n(alpha),  cos(alpha) = max(0, r . wi),
/// r = reflect(wo) the mirror direction. Zero when wo or wi is below the surface. Reciprocal because
/// reflect(wo) . wi = wo . reflect(wi).
Color evalPhong(const PhongMaterial& m, const Vec3& wo, const Vec3& wi);

/// The mirror direction of wo about the normal (+Z) in the local frame: r = 2 wo.z Z - wo = (-wo.x, -wo.y, wo.z),
/// the axis of the specular lobe (the one definition every estimator uses).
inline Vec3 mirrorDirection(const Vec3& wo) { return {-wo.x, -wo.y, wo.z}; }
/// The specular lobe's cosine of alpha for a pair of local directions: mirrorDirection(wo) . wi, clamped at 0.
inline double phongCosAlpha(const Vec3& wo, const Vec3& wi) { return std::max(0.0, dot(mirrorDirection(wo), wi)); }

/// I(n, theta) = integral over the hemisphere of cos^n(alpha) cos(theta') dw', where the lobe axis makes
/// the angle theta with the normal. Equals 2 pi / (n+2) at theta = 0; smaller once the horizon cuts the
/// lobe. Computed by adaptive Simpson quadrature to a relative error of about 1e-10 (see phong.cpp).
double phongLobeCosineIntegral(double n, double theta);

/// Directional albedo of the material seen from wo (local), i.e. the reflected radiance under a
/// constant incoming radiance L = 1:  rho_d + rho_s (n+2)/(2 pi) I(n, theta_o).
Color phongDirectionalAlbedo(const PhongMaterial& m, const Vec3& wo);

/// Scales rho_d and rho_s down per channel so that rho_d + rho_s <= 1; true when it had to.
bool clampEnergy(Color& rhoD, Color& rhoS);

/// The Phong approximation of a glTF metallic-roughness material (docs/scene-format.md): with base
/// colour b, metallic m, roughness r and a dielectric's reflectance F0 at normal incidence (0.04 unless
/// KHR_materials_specular or KHR_materials_ior say otherwise), rho_s = F0 (1 - m) + b m and
/// rho_d = b (1 - m) (1 - max(F0)): the dielectric's diffuse part gets what its specular layer does not
/// reflect, so that a white dielectric reflects 1 in all, not 1 + F0. n = 2 / alpha^2 - 2 with
/// alpha = max(r^2, 10^-3), clamped to [0, 10^4] (a Phong lobe about as wide as a GGX lobe of that alpha).
void metallicRoughnessToPhong(const Color& base, double metallic, double roughness, const Color& f0, Color& rhoD, Color& rhoS,
                              double& exponent);

/// Checks a material's numbers. Throws std::invalid_argument naming the offending value when a number is
/// not finite or negative; scales rho_d and rho_s down per channel so that rho_d + rho_s <= 1 and
/// returns true when it had to (the caller warns).
bool validateAndClampPhong(PhongMaterial& m);

}  // namespace symphong
