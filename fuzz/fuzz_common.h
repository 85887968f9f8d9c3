// fuzz/fuzz_common.h — the entry points of the fuzz targets, shared with tests/test_fuzz_regressions.cpp
// so that a regression input goes through exactly what the fuzzer ran: how each target turns its input
// bytes into files in a scratch directory of this process (under /dev/shm, else $TMPDIR or /tmp) and
// which loader it calls; the rule that symphong::InputError (MissingFileError included) is the
// expected rejection of bad input, while anything else that escapes is a finding; and the checks that
// what a loader *accepts* keeps its promises (scene/scene.h: "the layers below never see a NaN, a
// negative albedo or an out-of-range index"; a decoded texture holds width x height x channels finite
// texels >= 0). The fuzzers abort on a broken promise, so libFuzzer saves the input; the test reports it.
#pragma once

#include "estimators/estimator.h"
#include "io/input_error.h"
#include "render/checkpoint.h"
#include "render/renderer.h"
#include "render/settings.h"
#include "scene/scene.h"
#include "texture/texture_io.h"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

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

// ---- fuzz_ply: the PLY file (symphong's own reader, scene/ply_loader.cpp) --------------------------------

/// Writes "in.ply" into dir, emptied first, and loads it through loadScene.
inline Scene loadPlyInput(const fs::path& dir, std::string_view input) {
    clearDir(dir);
    const fs::path path = dir / "in.ply";
    writeBytes(path, input);
    return loadScene(path.string());
}

// ---- fuzz_checkpoint: one byte of flags, then the checkpoint file (render/checkpoint.cpp) ---------------

/// What readCheckpoint gave back.
struct CheckpointRead {
    RenderIdentity identity;
    RenderState state;
};

/// render/checkpoint.cpp's checksum (a copy of its private Hasher: the file format's definition), so
/// that the harness can make a mutated file's checksum right and the fuzzer gets past it to what the
/// reader checks after it and what the renderer does with what it accepts.
class CheckpointHasher {
public:
    void add(const void* data, std::size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        std::size_t i = 0;
        for (; i + 32 <= n; i += 32) {
            std::uint64_t w[4];
            std::memcpy(w, p + i, 32);
            for (int k = 0; k < 4; ++k) lane_[k] = mix(lane_[k], w[k]);
        }
        for (; i + 8 <= n; i += 8) {
            std::uint64_t w;
            std::memcpy(&w, p + i, 8);
            lane_[0] = mix(lane_[0], w);
        }
        std::uint64_t tail = 0;
        std::memcpy(&tail, p + i, n - i);
        lane_[0] = mix(lane_[0], tail ^ (static_cast<std::uint64_t>(n - i) << 56));
    }
    std::uint64_t value() const {
        std::uint64_t h = 0x243F6A8885A308D3ull;
        for (std::uint64_t l : lane_) h = mix(h, l);
        return h;
    }

private:
    static std::uint64_t mix(std::uint64_t h, std::uint64_t w) {
        h = (h ^ w) * 0x9E3779B97F4A7C15ull;
        return h ^ (h >> 29);
    }
    std::uint64_t lane_[4] = {1, 2, 3, 4};
};

constexpr std::string_view kCheckpointMagic = "symphong checkpoint 1\n";

/// The byte counts of the sections of a `--splitting ears` checkpoint after the pixel sections (render/
/// checkpoint.cpp forEachSection: factor cells 4 B each, their values 4 B x factor_values each, sum cells
/// 4 B each, their sums 48 B each), from its header's "ears" object; false when it has none the writer
/// could have written (counts that are not integers from 0 to 2^20; factor_values absent: 3, as in files
/// written before the first hit's MIS share).
inline bool earsSectionSizes(const nlohmann::json& ears, std::vector<std::size_t>& sizes) {
    if (!ears.is_object()) return false;
    const auto count = [&](const char* key, std::uint64_t absent, std::uint64_t& out) {
        if (!ears.contains(key)) {
            out = absent;
            return absent != ~std::uint64_t{0};
        }
        const nlohmann::json& v = ears[key];
        if (!v.is_number_unsigned() || v.get<std::uint64_t>() > (1u << 20)) return false;
        out = v.get<std::uint64_t>();
        return true;
    };
    std::uint64_t factorCells = 0, values = 0, sumCells = 0;
    if (!count("factor_cells", ~std::uint64_t{0}, factorCells) || !count("factor_values", 3, values) ||
        !count("sum_cells", ~std::uint64_t{0}, sumCells) || values > 16)
        return false;
    for (const std::uint64_t n : {factorCells * 4, factorCells * values * 4, sumCells * 4, sumCells * 48})
        sizes.push_back(static_cast<std::size_t>(n));
    return true;
}

/// The file with its last 8 bytes replaced by the checksum the writer would have put there, when the
/// file has the magic line, a header line whose width and height are integers of a small image, and
/// exactly the size that header calls for (tile counts, three sections of sums, and with an "ears" object
/// in the header the four sections of the learned splitting, earsSectionSizes; checksum); otherwise the
/// file as it is. Sections are hashed as the writer hashes them: magic, header line, then each section in
/// one piece (files under 64 MiB).
inline std::string withFixedChecksum(std::string file) {
    if (file.compare(0, kCheckpointMagic.size(), kCheckpointMagic) != 0) return file;
    const std::size_t eol = file.find('\n', kCheckpointMagic.size());
    if (eol == std::string::npos) return file;
    const std::size_t start = eol + 1;
    const nlohmann::json header = nlohmann::json::parse(file.begin() + static_cast<std::ptrdiff_t>(kCheckpointMagic.size()),
                                                        file.begin() + static_cast<std::ptrdiff_t>(start), nullptr, false);
    if (!header.is_object() || !header.contains("width") || !header.contains("height")) return file;
    const nlohmann::json &jw = header["width"], &jh = header["height"];
    if (!jw.is_number_integer() || !jh.is_number_integer()) return file;
    const std::int64_t w = jw.get<std::int64_t>(), h = jh.get<std::int64_t>();
    if (w < 1 || h < 1 || w > 4096 || h > 4096 || w * h > (1 << 16)) return file;
    const std::size_t pixels = static_cast<std::size_t>(w * h);
    const auto tiles = static_cast<std::size_t>(tileCount(static_cast<int>(w), static_cast<int>(h)));
    std::vector<std::size_t> sections = {tiles * 4, pixels * 24, pixels * 24, pixels * 8};
    if (header.contains("ears") && !earsSectionSizes(header["ears"], sections)) return file;
    std::size_t end = start;
    for (std::size_t n : sections) end += n;
    if (file.size() != end + 8) return file;
    CheckpointHasher hash;
    hash.add(file.data(), kCheckpointMagic.size());
    hash.add(file.data() + kCheckpointMagic.size(), start - kCheckpointMagic.size());
    std::size_t at = start;
    for (std::size_t n : sections) {
        hash.add(file.data() + at, n);
        at += n;
    }
    const std::uint64_t sum = hash.value();
    std::memcpy(file.data() + end, &sum, 8);
    return file;
}

/// Bit 0 of the first byte: make the checksum right (withFixedChecksum); the rest is the file, written
/// as "in.ckpt" into dir (emptied first) and read through readCheckpoint. An accepted checkpoint is then
/// used as `symphong render --resume` uses it: compared with the identity of a render (requireSameRender,
/// whose InputError is the expected answer to another render's checkpoint) and turned into its image,
/// variance and error. An empty input is an InputError.
inline CheckpointRead readCheckpointInput(const fs::path& dir, std::string_view input) {
    if (input.empty()) throw InputError("empty fuzz_checkpoint input (no flags byte)");
    clearDir(dir);
    std::string file(input.substr(1));
    if (static_cast<unsigned char>(input[0]) & 1) file = withFixedChecksum(std::move(file));
    const fs::path path = dir / "in.ckpt";
    writeBytes(path, file);
    CheckpointRead out;
    readCheckpoint(path.string(), out.identity, out.state);
    return out;
}

// ---- fuzz_settings: the value of a JSON scene's "render" key (render/settings.h) --------------------------

/// What `symphong render` made of a scene's "render" settings.
struct SettingsRead {
    RenderOptions options;
};

/// Writes "in.json", {"builtin": "cornell", "render": INPUT}, into dir (emptied first), loads it and does
/// what `symphong render in.json` does with its settings before it renders (cli/render_command.cpp,
/// render/long_render.cpp): applySceneSettings under no command-line options, checkRenderOptions, the
/// estimator (its std::invalid_argument is the command line's InputError), the stop rules and the
/// renderer's settings.
inline SettingsRead loadSettingsInput(const fs::path& dir, std::string_view input) {
    clearDir(dir);
    const fs::path path = dir / "in.json";
    writeBytes(path, "{\"builtin\": \"cornell\", \"render\": " + std::string(input) + "\n}\n");
    const Scene scene = loadScene(path.string());
    SettingsRead out;
    applySceneSettings(out.options, scene, path.string(), {});
    checkRenderOptions(out.options);
    try {
        (void)makeEstimator(out.options.estimator, out.options.estimatorOptions);
    } catch (const std::invalid_argument& e) {
        throw InputError(std::string("--estimator: ") + e.what());
    }
    (void)stopRules(out.options);
    (void)renderSettings(out.options);
    return out;
}

// ---- fuzz_gltf_ext: the "materials" of a glTF whose other parts are fixed (scene/assimp_materials.cpp) ----

/// A 2x2 RGB PNG, the glTF's one image (tex.png beside it).
constexpr unsigned char kTexPng[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00, 0x00,
    0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x02, 0x00, 0x00, 0x00, 0xfd, 0xd4, 0x9a, 0x73, 0x00, 0x00, 0x00, 0x12, 0x49,
    0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0xf8, 0xcf, 0xc0, 0xc0, 0x00, 0xc2, 0x0c, 0xff, 0x81, 0x00, 0x00, 0x1f, 0xee,
    0x05, 0xfb, 0x0b, 0xd9, 0x68, 0x8b, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

/// One triangle with normals and texture coordinates (one 96-byte buffer), its primitive using material 0;
/// textures 0 and 1 (tex.png, a sampler with REPEAT and MIRRORED_REPEAT); the materials are the input.
constexpr std::string_view kGltfBeforeMaterials =
    R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
"extensionsUsed": ["KHR_texture_transform", "KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_materials_specular"],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "material": 0}]}],
"buffers": [{"byteLength": 96, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAAAAAgD8AAIA/AACAPwAAAAAAAAAA"}],
"bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36}, {"buffer": 0, "byteOffset": 72, "byteLength": 24}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
              {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
              {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}],
"samplers": [{"wrapS": 10497, "wrapT": 33648}],
"images": [{"uri": "tex.png"}],
"textures": [{"source": 0, "sampler": 0}, {"source": 0}],
"materials": )";

/// Writes "in.gltf" (the fixed glTF above, its "materials" the input) and tex.png into dir, emptied
/// first, and loads it through loadScene: Assimp reads the glTF, symphong reads the materials' JSON
/// beside it (metallic-roughness, KHR_texture_transform, KHR_materials_ior / _specular /
/// _emissive_strength, normalTexture's scale, alphaMode).
inline Scene loadGltfExtInput(const fs::path& dir, std::string_view input) {
    clearDir(dir);
    writeBytes(dir / "tex.png", std::string_view(reinterpret_cast<const char*>(kTexPng), sizeof kTexPng));
    const fs::path path = dir / "in.gltf";
    writeBytes(path, std::string(kGltfBeforeMaterials) + std::string(input) + "\n}\n");
    return loadScene(path.string());
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

/// What is wrong with a checkpoint readCheckpoint accepted, or "": its sections sized for its image and
/// tiles, no tile past the spp, finite sums and non-negative sums of squares (the renderer discards
/// non-finite samples, so a checkpoint it wrote has no other), then what a resumed render does with
/// it: requireSameRender against another render (InputError, the expected answer, is caught here), the
/// image and its variance, finite where the state is.
/// What is wrong with learned splitting factors (splitting/ears.h Factors), or "": none at all, or every
/// table one entry a grid cell, each entry what learnFactors can put there (Factors::learnedValue), and a
/// finite scale >= 0.
inline std::string earsFactorsProblem(const ears::Factors& f) {
    if (f.empty()) return {};
    if (!std::isfinite(f.scale) || f.scale < 0) return "a scale of " + std::to_string(f.scale);
    const auto tables = f.tables();
    for (std::size_t t = 0; t < tables.size(); ++t) {
        const std::vector<float>& table = *tables[t];
        if (table.size() != ears::Grid::cellCount())
            return "factor table " + std::to_string(t) + " of " + std::to_string(table.size()) + " cells";
        for (std::size_t c = 0; c < table.size(); ++c)
            if (!f.learnedValue(table, table[c]))
                return "factor table " + std::to_string(t) + " holds " + std::to_string(table[c]) + " in cell " + std::to_string(c);
    }
    return {};
}

inline std::string checkpointProblem(const CheckpointRead& c) {
    const RenderState& s = c.state;
    if (s.width < 1 || s.height < 1 || s.sppBound < 1) return "accepted a state of " + std::to_string(s.width) + " x " +
                                                              std::to_string(s.height) + " at spp " + std::to_string(s.sppBound);
    const std::size_t pixels = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
    if (s.sum.size() != pixels || s.sumSq.size() != pixels || s.sumLuminanceSq.size() != pixels ||
        s.tileSamples.size() != static_cast<std::size_t>(tileCount(s.width, s.height)))
        return "the sections are not sized for the image and its tiles";
    for (std::uint32_t n : s.tileSamples)
        if (n > s.sppBound) return "a tile has " + std::to_string(n) + " samples, past spp " + std::to_string(s.sppBound);
    for (std::size_t i = 0; i < pixels; ++i)
        if (!isFinite(s.sum[i]) || !nonNegativeFinite(s.sumSq[i]) || !(s.sumLuminanceSq[i] >= 0) || !std::isfinite(s.sumLuminanceSq[i]))
            return "pixel " + std::to_string(i) + " has a non-finite sum or a negative or non-finite sum of squares";
    if (!std::isfinite(s.seconds) || s.seconds < 0 || !std::isfinite(s.cpuSeconds) || s.cpuSeconds < 0)
        return "accepted a render time that is not finite and >= 0";
    RenderIdentity now{"cornell", "0123456789abcdef", nlohmann::json{{"spp", 64}, {"width", 512}}};
    try {
        requireSameRender("in.ckpt", c.identity, now);
        requireSameRender("in.ckpt", c.identity, c.identity);
    } catch (const InputError&) {
    }
    const Image image = s.image(), variance = s.variance();
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x)
            if (!isFinite(image.at(x, y)) || !isFinite(variance.at(x, y)))
                return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") of the resumed image or variance is not finite";
    if (s.ears) {
        // --splitting ears: the factors read, and those that the epoch's end learns from the sums read
        // (what the resumed render does next), are what learnFactors promises.
        if (const std::string p = earsFactorsProblem(s.ears->factors); !p.empty()) return "as read, " + p;
        ears::Learning next = *s.ears;
        next.advance(s.variancePerSample(), s.rays, s.samples, s.paths, true);
        if (const std::string p = earsFactorsProblem(next.factors); !p.empty()) return "learned from the sums read, " + p;
    }
    return {};
}

/// What is wrong with render options that were accepted, or "": within the schema's ranges as
/// checkRenderOptions and the schema promise, and the same options again when written with toJson and
/// read back with fromJson (what a checkpoint's identity and the study's config rely on).
inline std::string settingsProblem(const SettingsRead& r) {
    const RenderOptions& o = r.options;
    if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384 || o.spp < 1)
        return "accepted an image of " + std::to_string(o.width) + " x " + std::to_string(o.height) + " at spp " + std::to_string(o.spp);
    if (!std::isfinite(o.exposure) || !std::isfinite(o.time) || o.time < 0 || !std::isfinite(o.targetError) || o.targetError < 0)
        return "accepted a non-finite or negative exposure, time or target error";
    const nlohmann::json written = schema::toJson(o, renderSchema());
    RenderOptions again;
    try {
        schema::fromJson(written, again, renderSchema());
    } catch (const std::invalid_argument& e) {
        return std::string("accepted options that do not read back: ") + e.what() + " in " + written.dump();
    }
    if (schema::toJson(again, renderSchema()) != written) return "options read back differently: " + written.dump();
    return {};
}

inline std::string problem(const Scene& s) { return sceneProblem(s); }
inline std::string problem(const CheckpointRead& c) { return checkpointProblem(c); }
inline std::string problem(const SettingsRead& r) { return settingsProblem(r); }
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
