// `symphong info`: what a scene file holds, as symphong loads it (render/describe.h).
#include "cli/commands.h"
#include "render/describe.h"
#include "scene/scene.h"

#include <fmt/format.h>

namespace symphong {

void addInfoCommand(CLI::App& app, std::string& scene) {
    CLI::App* i = app.add_subcommand("info", "Print what a scene file holds, as symphong loads it, without rendering.");
    i->footer(
        "Triangles and vertices, the bounding box, the camera (given, or the automatic one), every material with its\n"
        "Phong parameters (rho_d, rho_s, n, emission) and how many triangles use it, the lights (point, spot,\n"
        "directional; the default sky's sun when the scene brings no light), the environment (constant, default sky or\n"
        "an HDR map), the textures (size, channels, wrap modes, and which material uses each for what), and the\n"
        "loader's warnings (a missing texture file is one).");
    i->add_option("scene", scene, "cornell, FILE.obj, FILE.gltf/.glb/.ply/.fbx/.dae/.3ds or FILE.json")->capture_default_str();
}

int runInfo(const std::string& spec) {
    const Scene s = loadScene(spec);
    for (const std::string& w : s.warnings) fmt::print(stderr, "symphong: warning: {}\n", w);
    fmt::print("{}", describeScene(s, spec));
    return 0;
}

}  // namespace symphong
