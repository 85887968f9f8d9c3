#include "scene/exporter_conventions.h"

#include <algorithm>
#include <cstring>
#include <fstream>

namespace symphong {

bool mtlWrittenByBlender(const std::string& text) { return text.rfind("# Blender", 0) == 0; }

bool fbxWrittenByBlender(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::string head(64 * 1024, '\0');  // an FBX names its creator in its header extension, near the start
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    const bool fbx = head.rfind("Kaydara FBX Binary", 0) == 0 || head.find("FBXHeaderExtension") != std::string::npos;
    return fbx && (head.find("Blender (stable FBX IO)") != std::string::npos || head.find("Creator: \"Blender") != std::string::npos);
}

bool colladaWrittenByBlender(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::string head(16 * 1024, '\0');  // <asset><contributor><authoring_tool> comes first in a COLLADA document
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    const auto tool = head.find("<authoring_tool>");
    return tool != std::string::npos && head.compare(tool + 16, 7, "Blender") == 0;
}

void blenderPrincipledToPhong(const Color& base, double metallic, double specular, double roughness, Color& rhoD, Color& rhoS,
                              double& exponent) {
    const double f0 = std::clamp(0.08 * specular, 0.0, 1.0);
    metallicRoughnessToPhong(base, std::clamp(metallic, 0.0, 1.0), std::clamp(roughness, 0.0, 1.0), Color(f0), rhoD, rhoS, exponent);
}

}  // namespace symphong
