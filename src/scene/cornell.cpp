#include "scene/scene.h"

#include <initializer_list>

namespace symphong {

namespace {

void addQuad(Scene& s, std::initializer_list<Vec3> corners, std::uint32_t material) {
    const auto base = static_cast<std::uint32_t>(s.positions.size());
    for (const Vec3& c : corners) s.positions.push_back(c);
    s.triangles.push_back({{base, base + 1, base + 2}, {-1, -1, -1}, material});
    s.triangles.push_back({{base, base + 2, base + 3}, {-1, -1, -1}, material});
}

}  // namespace

// Geometry: the Cornell Program of Computer Graphics' measured box (millimetres), as distributed at
// graphics.cornell.edu/online/box/data.html. The light is moved 0.1 below the ceiling so the two do not
// coincide; its winding makes it face down. Colours follow the common RGB fit of the measured spectra.
Scene makeCornellBox() {
    Scene s;
    s.name = "cornell";
    auto material = [&](const char* name, Color kd, Color ks, double n, Color ke) {
        PhongMaterial m;
        m.name = name;
        m.rhoD = kd;
        m.rhoS = ks;
        m.exponent = n;
        m.emission = ke;
        s.materials.push_back(m);
        return static_cast<std::uint32_t>(s.materials.size() - 1);
    };
    const auto white = material("white", {0.725, 0.71, 0.68}, Color(0.0), 1.0, Color(0.0));
    const auto red = material("red", {0.63, 0.065, 0.05}, Color(0.0), 1.0, Color(0.0));
    const auto green = material("green", {0.14, 0.45, 0.091}, Color(0.0), 1.0, Color(0.0));
    const auto glossy = material("tallBlock", {0.3, 0.3, 0.3}, Color(0.45), 60.0, Color(0.0));
    const auto light = material("light", {0.78, 0.78, 0.78}, Color(0.0), 1.0, {17.0, 12.0, 4.0});

    addQuad(s, {{552.8, 0, 0}, {0, 0, 0}, {0, 0, 559.2}, {549.6, 0, 559.2}}, white);                  // floor
    addQuad(s, {{556, 548.8, 0}, {556, 548.8, 559.2}, {0, 548.8, 559.2}, {0, 548.8, 0}}, white);      // ceiling
    addQuad(s, {{549.6, 0, 559.2}, {0, 0, 559.2}, {0, 548.8, 559.2}, {556, 548.8, 559.2}}, white);    // back
    addQuad(s, {{0, 0, 559.2}, {0, 0, 0}, {0, 548.8, 0}, {0, 548.8, 559.2}}, green);                  // right
    addQuad(s, {{552.8, 0, 0}, {549.6, 0, 559.2}, {556, 548.8, 559.2}, {556, 548.8, 0}}, red);        // left
    addQuad(s, {{343, 548.7, 227}, {343, 548.7, 332}, {213, 548.7, 332}, {213, 548.7, 227}}, light);  // light

    // short block
    addQuad(s, {{130, 165, 65}, {82, 165, 225}, {240, 165, 272}, {290, 165, 114}}, white);
    addQuad(s, {{290, 0, 114}, {290, 165, 114}, {240, 165, 272}, {240, 0, 272}}, white);
    addQuad(s, {{130, 0, 65}, {130, 165, 65}, {290, 165, 114}, {290, 0, 114}}, white);
    addQuad(s, {{82, 0, 225}, {82, 165, 225}, {130, 165, 65}, {130, 0, 65}}, white);
    addQuad(s, {{240, 0, 272}, {240, 165, 272}, {82, 165, 225}, {82, 0, 225}}, white);
    // tall block (glossy)
    addQuad(s, {{423, 330, 247}, {265, 330, 296}, {314, 330, 456}, {472, 330, 406}}, glossy);
    addQuad(s, {{423, 0, 247}, {423, 330, 247}, {472, 330, 406}, {472, 0, 406}}, glossy);
    addQuad(s, {{472, 0, 406}, {472, 330, 406}, {314, 330, 456}, {314, 0, 456}}, glossy);
    addQuad(s, {{314, 0, 456}, {314, 330, 456}, {265, 330, 296}, {265, 0, 296}}, glossy);
    addQuad(s, {{265, 0, 296}, {265, 330, 296}, {423, 330, 247}, {423, 0, 247}}, glossy);

    s.camera.position = {278, 273, -800};
    s.camera.target = {278, 273, -799};
    s.camera.up = {0, 1, 0};
    s.camera.fovY = 39.3077;
    return s;
}

}  // namespace symphong
