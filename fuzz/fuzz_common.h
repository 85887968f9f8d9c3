// fuzz/fuzz_common.h — the entry points of the fuzz targets, shared with tests/test_fuzz_regressions.cpp
// so that a regression input goes through exactly what the fuzzer ran: how each target turns its input
// bytes into files in a scratch directory of this process (under /dev/shm, else $TMPDIR or /tmp) and
// which loader it calls; the rule that symphong::InputError (MissingFileError included) is the
// expected rejection of bad input, while anything else that escapes is a finding; and the checks that
// what a loader *accepts* keeps its promises (scene/scene.h: "the layers below never see a NaN, a
// negative albedo or an out-of-range index"; a decoded texture holds width x height x channels finite
// texels >= 0). The fuzzers abort on a broken promise, so libFuzzer saves the input; the test reports it.
#pragma once

#include "io/input_error.h"
#include "scene/scene.h"
#include "texture/texture_io.h"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace symphong::fuzz {

namespace fs = std::filesystem;

/// A scratch directory of this process, created on first use and removed at a normal exit. Every process
/// (libFuzzer's -fork children, parallel jobs) gets its own, so runs never see each other's files.
inline const fs::path& scratchDir(const char* target) {
    static const fs::path dir = [&] {
        fs::path base = "/dev/shm";
        std::error_code ec;
        if (!fs::is_directory(base, ec) || ::access(base.c_str(), W_OK) != 0) {
            const char* tmp = std::getenv("TMPDIR");
            base = tmp && *tmp ? tmp : "/tmp";
        }
        fs::path d = base / ("symphong-fuzz-" + std::string(target) + "-" + std::to_string(::getpid()));
        fs::create_directories(d);
        static const fs::path forExit = d;
        std::atexit([] {
            std::error_code e;
            fs::remove_all(forExit, e);
        });
        return d;
    }();
    return dir;
}

/// Empties a directory, so that one input never sees the files of the one before.
inline void clearDir(const fs::path& dir) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) fs::remove_all(entry.path(), ec);
}

inline void writeBytes(const fs::path& path, std::string_view bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) {
        std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
        std::abort();  // a harness problem, not a finding: stop loudly
    }
}

// ---- fuzz_obj: the OBJ text, optionally a line "#==MTL==" and the text of its material library -----

constexpr std::string_view kMtlSeparator = "#==MTL==";

/// The file name of the OBJ's first `mtllib`, when it is a plain name (no directory part); else "in.mtl".
inline std::string mtlName(std::string_view obj) {
    std::size_t pos = 0;
    while (pos < obj.size()) {
        std::size_t end = obj.find('\n', pos);
        if (end == std::string_view::npos) end = obj.size();
        std::string_view line = obj.substr(pos, end - pos);
        pos = end + 1;
        while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
        if (line.substr(0, 7) != "mtllib " && line.substr(0, 7) != "mtllib\t") continue;
        line.remove_prefix(7);
        while (!line.empty() && std::isspace(static_cast<unsigned char>(line.front()))) line.remove_prefix(1);
        std::size_t n = 0;
        while (n < line.size() && !std::isspace(static_cast<unsigned char>(line[n]))) ++n;
        const std::string name(line.substr(0, n));
        bool plain = !name.empty() && name.size() < 64 && name != "." && name != ".." && name != "in.obj";
        for (char c : name) plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-');
        return plain ? name : "in.mtl";
    }
    return "in.mtl";
}

/// Writes "in.obj" (and its MTL) into dir, emptied first, and loads it through loadScene.
inline Scene loadObjInput(const fs::path& dir, std::string_view input) {
    clearDir(dir);
    std::string_view obj = input;
    for (std::size_t at = input.find(kMtlSeparator); at != std::string_view::npos; at = input.find(kMtlSeparator, at + 1)) {
        if (at != 0 && input[at - 1] != '\n') continue;  // the separator starts a line
        obj = input.substr(0, at);
        const std::size_t rest = at + kMtlSeparator.size();
        const std::string_view mtl = rest < input.size() && input[rest] == '\n' ? input.substr(rest + 1) : input.substr(rest);
        writeBytes(dir / mtlName(obj), mtl);
        break;
    }
    const fs::path path = dir / "in.obj";
    writeBytes(path, obj);
    return loadScene(path.string());
}

// ---- fuzz_json: the JSON text, beside fixed files it may name -----------------------------------------

constexpr const char* kFloorObj =
    "mtllib floor.mtl\nv -5 0 -5\nv -5 0 5\nv 5 0 5\nv 5 0 -5\nvn 0 1 0\nusemtl floor\nf 1//1 2//1 3//1 4//1\n";
constexpr const char* kFloorMtl = "newmtl floor\nKd 0.5 0.5 0.5\nKs 0.2 0.2 0.2\nNs 20\n";
constexpr const char* kLampObj = "mtllib lamp.mtl\nv -1 2 -1\nv 1 2 -1\nv 1 2 1\nv -1 2 1\nusemtl lamp\nf 1 2 3 4\n";
constexpr const char* kLampMtl = "newmtl lamp\nKd 0 0 0\nKe 10 10 10\n";
// One triangle, its positions in a base64 data URI (the glTF of tests/test_assimp.cpp, shortened).
constexpr const char* kTriGltf = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
"materials": [{"name": "metal", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1], "metallicFactor": 0.25, "roughnessFactor": 0.5}}],
"buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIC/"}],
"bufferViews": [{"buffer": 0, "byteLength": 36}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]}]})";
constexpr const char* kTriPly =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

/// Writes "in.json" beside floor.obj (+ floor.mtl, material "floor"), lamp.obj (+ lamp.mtl: an emissive
/// quad, material "lamp"), tri.gltf and tri.ply into dir, emptied first, and loads it through loadScene.
inline Scene loadJsonInput(const fs::path& dir, std::string_view input) {
    clearDir(dir);
    writeBytes(dir / "floor.obj", kFloorObj);
    writeBytes(dir / "floor.mtl", kFloorMtl);
    writeBytes(dir / "lamp.obj", kLampObj);
    writeBytes(dir / "lamp.mtl", kLampMtl);
    writeBytes(dir / "tri.gltf", kTriGltf);
    writeBytes(dir / "tri.ply", kTriPly);
    const fs::path path = dir / "in.json";
    writeBytes(path, input);
    return loadScene(path.string());
}

// ---- fuzz_assimp: one byte for the extension, then the file ---------------------------------------------

constexpr const char* kAssimpExtensions[6] = {".gltf", ".glb", ".ply", ".fbx", ".dae", ".3ds"};

/// Writes "in.<ext>" into dir, emptied first, the extension by the first byte % 6 (.gltf .glb .ply .fbx
/// .dae .3ds), the rest the file, and loads it through loadScene. An empty input is an InputError.
inline Scene loadAssimpInput(const fs::path& dir, std::string_view input) {
    if (input.empty()) throw InputError("empty fuzz_assimp input (no extension byte)");
    clearDir(dir);
    const fs::path path = dir / (std::string("in") + kAssimpExtensions[static_cast<unsigned char>(input[0]) % 6]);
    writeBytes(path, input.substr(1));
    return loadScene(path.string());
}

// ---- fuzz_texture: one byte for the encoding, then the image ----------------------------------------------

/// Decodes the image after the first byte, whose bit 0 picks the encoding (0 sRGB, 1 linear). An empty
/// input is an InputError.
inline Texture decodeTextureInput(std::string_view input) {
    if (input.empty()) throw InputError("empty fuzz_texture input (no encoding byte)");
    const auto encoding = (static_cast<unsigned char>(input[0]) & 1) ? TextureEncoding::Linear : TextureEncoding::Srgb;
    return decodeTexture("input", reinterpret_cast<const unsigned char*>(input.data()) + 1, input.size() - 1, encoding);
}

// ---- the promises of what a loader accepts ----------------------------------------------------------------

inline bool nonNegativeFinite(const Color& c) { return isFinite(c) && minComponent(c) >= 0; }

inline std::string textureRefProblem(const TextureRef& r, std::size_t textures) {
    if (r.index < -1 || (r.index >= 0 && static_cast<std::size_t>(r.index) >= textures))
        return "texture index " + std::to_string(r.index) + " out of range (" + std::to_string(textures) + " textures)";
    for (double x : r.transform)
        if (!std::isfinite(x)) return "a texture's transform (scale, offset, rotation) is not finite";
    return {};
}

/// What is wrong with a decoded texture, or "" (width x height x channels finite texels >= 0, 1 to 4
/// channels).
inline std::string textureProblem(const Texture& t) {
    if (t.width() <= 0 || t.height() <= 0 || t.channels() < 1 || t.channels() > 4)
        return "texture '" + t.name() + "' is " + std::to_string(t.width()) + " x " + std::to_string(t.height()) + " x " +
               std::to_string(t.channels());
    const std::uint64_t n =
        static_cast<std::uint64_t>(t.width()) * static_cast<std::uint64_t>(t.height()) * static_cast<std::uint64_t>(t.channels());
    if (t.bytes() != n * sizeof(float))
        return "texture '" + t.name() + "' holds " + std::to_string(t.bytes()) + " bytes, not width x height x channels floats";
    for (int y = 0; y < t.height(); ++y)
        for (int x = 0; x < t.width(); ++x)
            for (int c = 0; c < t.channels(); ++c) {
                const float v = t.texel(x, y, c);
                if (!(v >= 0) || !std::isfinite(v))
                    return "texture '" + t.name() + "' texel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                           std::to_string(c) + " is " + std::to_string(v);
            }
    return {};
}

/// What is wrong with a scene a loader returned (after finalizeScene), or "".
inline std::string sceneProblem(const Scene& s) {
    if (s.triangles.empty()) return "no triangles";
    for (std::size_t i = 0; i < s.triangles.size(); ++i) {
        const Triangle& t = s.triangles[i];
        const std::string tri = "triangle " + std::to_string(i);
        for (std::size_t k = 0; k < 3; ++k) {
            if (t.v[k] >= s.positions.size())
                return tri + " vertex index " + std::to_string(t.v[k]) + " >= " + std::to_string(s.positions.size()) + " positions";
            if (!isFinite(s.positions[t.v[k]])) return tri + " uses a non-finite position (index " + std::to_string(t.v[k]) + ")";
            if (t.n[k] < -1 || (t.n[k] >= 0 && static_cast<std::size_t>(t.n[k]) >= s.normals.size()))
                return tri + " normal index " + std::to_string(t.n[k]) + " out of range (" + std::to_string(s.normals.size()) + " normals)";
            if (t.n[k] >= 0) {
                const Vec3& n = s.normals[static_cast<std::size_t>(t.n[k])];
                if (!isFinite(n) || std::abs(length(n) - 1.0) > 1e-3)
                    return tri + " uses a normal that is not finite and of unit length (index " + std::to_string(t.n[k]) + ")";
            }
            if (t.t[k] < -1 || (t.t[k] >= 0 && static_cast<std::size_t>(t.t[k]) >= s.uvs.size()))
                return tri + " texture coordinate index " + std::to_string(t.t[k]) + " out of range (" + std::to_string(s.uvs.size()) + ")";
            if (t.t[k] >= 0) {
                const auto& uv = s.uvs[static_cast<std::size_t>(t.t[k])];
                if (!std::isfinite(uv[0]) || !std::isfinite(uv[1])) return tri + " uses non-finite texture coordinates";
            }
            if (t.tg[k] < -1 || (t.tg[k] >= 0 && static_cast<std::size_t>(t.tg[k]) >= s.tangents.size()))
                return tri + " tangent index " + std::to_string(t.tg[k]) + " out of range (" + std::to_string(s.tangents.size()) + ")";
            if (t.tg[k] >= 0 && !isFinite(s.tangents[static_cast<std::size_t>(t.tg[k])].t)) return tri + " uses a non-finite tangent";
        }
        if (t.material >= s.materials.size())
            return tri + " material " + std::to_string(t.material) + " >= " + std::to_string(s.materials.size()) + " materials";
    }
    for (const PhongMaterial& m : s.materials) {
        const std::string mat = "material '" + m.name + "'";
        if (!nonNegativeFinite(m.rhoD) || !nonNegativeFinite(m.rhoS) || !nonNegativeFinite(m.emission))
            return mat + " has a non-finite or negative colour";
        if (!std::isfinite(m.exponent) || m.exponent < 0) return mat + " has a non-finite or negative exponent";
        for (int c = 0; c < 3; ++c)
            if (m.rhoD[c] + m.rhoS[c] > 1.0 + 1e-9) return mat + " reflects more than it receives (Kd + Ks > 1)";
        const MaterialTextures& tx = m.textures;
        for (const TextureRef* r :
             {&tx.diffuse, &tx.specular, &tx.exponent, &tx.metallicRoughness, &tx.emission, &tx.alpha, &tx.normal, &tx.bump})
            if (std::string p = textureRefProblem(*r, s.textures.size()); !p.empty()) return mat + ": " + p;
        if (!std::isfinite(tx.normalScale) || !std::isfinite(tx.bumpScale)) return mat + " has a non-finite normal or bump scale";
        if (!nonNegativeFinite(tx.baseColor) || !std::isfinite(tx.metallic) || !std::isfinite(tx.roughness))
            return mat + " has non-finite metallic-roughness factors";
    }
    for (const Texture& t : s.textures)
        if (std::string p = textureProblem(t); !p.empty()) return p;
    for (std::size_t i = 0; i < s.lights.size(); ++i) {
        const Light& l = s.lights[i];
        if (!isFinite(l.position) || !isFinite(l.direction) || !nonNegativeFinite(l.intensity) || !std::isfinite(l.cosInner) ||
            !std::isfinite(l.cosOuter))
            return "light " + std::to_string(i) + " has a non-finite or negative value";
        if (std::abs(length(l.direction) - 1.0) > 1e-6) return "light " + std::to_string(i) + " direction is not of unit length";
    }
    if (!nonNegativeFinite(s.environment)) return "environment radiance is non-finite or negative";
    const Camera& c = s.camera;
    if (!isFinite(c.position) || !isFinite(c.target) || !isFinite(c.up) || !(c.fovY > 0 && c.fovY < 180))
        return "camera is non-finite or its field of view is outside (0, 180)";
    return {};
}

inline std::string problem(const Scene& s) { return sceneProblem(s); }
inline std::string problem(const Texture& t) { return textureProblem(t); }

/// The fuzzers' verdict on one input: returns when the loader accepts what keeps its promises or rejects
/// it with InputError; a broken promise aborts (libFuzzer saves the input); any other exception
/// propagates out of LLVMFuzzerTestOneInput and ends the process (std::terminate), which libFuzzer
/// reports as well.
template <class Load>
int runOne(Load&& load) {
    try {
        const auto result = load();
        if (const std::string p = problem(result); !p.empty()) {
            std::fprintf(stderr, "==symphong-fuzz== accepted input breaks the loader's promise: %s\n", p.c_str());
            std::fflush(stderr);
            std::abort();
        }
    } catch (const InputError& e) {
        // The expected rejection of bad input. SYMPHONG_FUZZ_VERBOSE=1 prints it, to see how far a seed gets.
        static const bool verbose = std::getenv("SYMPHONG_FUZZ_VERBOSE") != nullptr;
        if (verbose) std::fprintf(stderr, "rejected: %s\n", e.what());
    }
    return 0;
}

}  // namespace symphong::fuzz
