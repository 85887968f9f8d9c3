#include "scene/tangents.h"

#include "math/frame.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <unordered_map>

namespace symphong {

namespace {

Vec3 position(const Scene& s, const Triangle& tri, int k) { return s.positions[tri.v[static_cast<std::size_t>(k)]]; }

/// The angle of the triangle at corner k (its weight in the vertex's average, as in MikkTSpace).
double cornerAngle(const Scene& s, const Triangle& tri, int k) {
    const Vec3 p = position(s, tri, k);
    const Vec3 a = position(s, tri, (k + 1) % 3) - p, b = position(s, tri, (k + 2) % 3) - p;
    const double la = length(a), lb = length(b);
    if (!(la > 0 && lb > 0)) return 0.0;
    return std::acos(std::clamp(dot(a, b) / (la * lb), -1.0, 1.0));
}

/// v minus its component along the unit vector n, normalised; zero when nothing is left.
Vec3 projectOut(const Vec3& v, const Vec3& n) {
    const Vec3 p = v - n * dot(n, v);
    const double len = length(p);
    return len > 1e-300 && std::isfinite(len) ? p / len : Vec3(0.0);
}

}  // namespace

bool uvDerivatives(const Scene& scene, const Triangle& tri, Vec3& dpdu, Vec3& dpdv) {
    const Vec3 e1 = position(scene, tri, 1) - position(scene, tri, 0);
    const Vec3 e2 = position(scene, tri, 2) - position(scene, tri, 0);
    if (tri.t[0] < 0) {
        dpdu = e1, dpdv = e2;
        return true;
    }
    const auto& t0 = scene.uvs[static_cast<std::size_t>(tri.t[0])];
    const auto& t1 = scene.uvs[static_cast<std::size_t>(tri.t[1])];
    const auto& t2 = scene.uvs[static_cast<std::size_t>(tri.t[2])];
    const double du1 = t1[0] - t0[0], dv1 = t1[1] - t0[1], du2 = t2[0] - t0[0], dv2 = t2[1] - t0[1];
    // [du1 dv1; du2 dv2] [dp/du; dp/dv] = [e1; e2]
    const double det = du1 * dv2 - du2 * dv1;
    const double scale = std::max({std::abs(du1), std::abs(dv1), std::abs(du2), std::abs(dv2)});
    if (!(std::abs(det) > 1e-12 * scale * scale) || !std::isfinite(det)) return false;
    dpdu = (e1 * dv2 - e2 * dv1) / det;
    dpdv = (e2 * du1 - e1 * du2) / det;
    return true;
}

int handedness(const Scene& scene, const Triangle& tri, const Vec3& dpdu, const Vec3& dpdv) {
    const Vec3 n = cornerNormal(scene, tri, 0) + cornerNormal(scene, tri, 1) + cornerNormal(scene, tri, 2);
    return dot(cross(n, dpdu), dpdv) < 0 ? -1 : 1;
}

Vec3 cornerNormal(const Scene& scene, const Triangle& tri, int k) {
    if (tri.n[0] >= 0) return scene.normals[static_cast<std::size_t>(tri.n[static_cast<std::size_t>(k)])];
    const Vec3 c = cross(position(scene, tri, 1) - position(scene, tri, 0), position(scene, tri, 2) - position(scene, tri, 0));
    const double len = length(c);
    return len > 0 ? c / len : Vec3(0, 0, 1);
}

std::size_t computeTangents(Scene& scene) {
    // A vertex of the tangent space: position, normal, texture coordinate and handedness.
    using Key = std::tuple<std::uint32_t, std::int32_t, std::int32_t, int>;
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = std::get<0>(k);
            h = h * 0x9E3779B97F4A7C15ull + static_cast<std::uint32_t>(std::get<1>(k));
            h = h * 0x9E3779B97F4A7C15ull + static_cast<std::uint32_t>(std::get<2>(k));
            h = h * 0x9E3779B97F4A7C15ull + static_cast<std::uint32_t>(std::get<3>(k) + 1);
            return static_cast<std::size_t>(h ^ (h >> 29));
        }
    };
    struct Sum {
        Vec3 t{0.0};
        std::int32_t index = -1;
    };
    std::unordered_map<Key, Sum, KeyHash> sums;
    std::vector<std::size_t> todo;
    std::vector<int> signs;  // per entry of todo: +1, -1, or 0 where the triangle's uvs are degenerate
    std::vector<Vec3> faceTangent;
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
        const Triangle& tri = scene.triangles[i];
        if (tri.tg[0] >= 0 || !scene.materials[tri.material].textures.perturbsNormal()) continue;
        Vec3 dpdu, dpdv;
        int sign = 0;
        if (uvDerivatives(scene, tri, dpdu, dpdv)) {
            sign = handedness(scene, tri, dpdu, dpdv);
            for (int k = 0; k < 3; ++k) {
                const Key key{tri.v[static_cast<std::size_t>(k)], tri.n[static_cast<std::size_t>(k)], tri.t[static_cast<std::size_t>(k)], sign};
                sums[key].t += projectOut(dpdu, cornerNormal(scene, tri, k)) * cornerAngle(scene, tri, k);
            }
        }
        todo.push_back(i);
        signs.push_back(sign);
    }
    for (std::size_t j = 0; j < todo.size(); ++j) {
        Triangle& tri = scene.triangles[todo[j]];
        for (int k = 0; k < 3; ++k) {
            const std::size_t c = static_cast<std::size_t>(k);
            const Vec3 n = cornerNormal(scene, tri, k);
            // A triangle with degenerate uvs borrows the tangent of a neighbour at the same vertex.
            Sum* sum = nullptr;
            for (int sign : {signs[j], 1, -1}) {
                if (sign == 0) continue;
                const auto it = sums.find(Key{tri.v[c], tri.n[c], tri.t[c], sign});
                if (it != sums.end() && length(it->second.t) > 0) {
                    sum = &it->second;
                    if (sum->index < 0) {
                        Vec3 t = projectOut(sum->t, n);
                        if (length(t) == 0) t = Frame::fromNormal(n).s;
                        scene.tangents.push_back({t, static_cast<double>(sign)});
                        sum->index = static_cast<std::int32_t>(scene.tangents.size() - 1);
                    }
                    break;
                }
            }
            if (sum) {
                tri.tg[c] = sum->index;
            } else {  // no triangle at this vertex has usable uvs: any tangent will do
                scene.tangents.push_back({Frame::fromNormal(n).s, 1.0});
                tri.tg[c] = static_cast<std::int32_t>(scene.tangents.size() - 1);
            }
        }
    }
    return todo.size();
}

}  // namespace symphong
