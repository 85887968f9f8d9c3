// PLY (Stanford polygon file format), read by our own reader rather than Assimp: Assimp 5.2 reads only
// the first triangle of a mesh stored as triangle strips (`element tristrips`, common in scanned data),
// silently. ASCII and binary (either byte order); vertices with x, y, z and optional normals (nx, ny, nz)
// and texture coordinates (u/v, s/t, texture_u/texture_v, texture_s/texture_t); faces as polygons
// (fanned into triangles) and triangle strips (-1 restarts a strip; every other triangle reversed so that
// all keep the strip's winding; the strips' zero-area joining triangles dropped). Other elements and
// properties are read past. A PLY has no materials: the mesh gets the same neutral default as an OBJ
// without an MTL. Every count the header declares is read in full or the file is refused, naming what
// is missing; what was read is compared with what was declared and said when they differ.
#include "scene/scene.h"

#include "io/files.h"
#include "io/input_error.h"
#include "io/memory.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace symphong {

namespace {

enum class PlyType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32;
    bool list = false;
    PlyType countType = PlyType::Uint8;
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    enum Format { Ascii, BinaryLittle, BinaryBig } format = Ascii;
    std::vector<PlyElement> elements;
    std::size_t dataStart = 0;  ///< byte offset of the data after "end_header\n"
    int lines = 0;              ///< lines of the header (ASCII data's line numbers follow)
};

PlyType plyType(const std::string& name, const std::string& where) {
    static const std::pair<const char*, PlyType> kTypes[] = {
        {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::Uint8},     {"uint8", PlyType::Uint8},
        {"short", PlyType::Int16},   {"int16", PlyType::Int16},     {"ushort", PlyType::Uint16},   {"uint16", PlyType::Uint16},
        {"int", PlyType::Int32},     {"int32", PlyType::Int32},     {"uint", PlyType::Uint32},     {"uint32", PlyType::Uint32},
        {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64}, {"float64", PlyType::Float64}};
    for (const auto& [n, t] : kTypes)
        if (name == n) return t;
    throw InputError(fmt::format("{}: unknown property type '{}'", where, name));
}

int typeSize(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::Uint8:
            return 1;
        case PlyType::Int16:
        case PlyType::Uint16:
            return 2;
        case PlyType::Float64:
            return 8;
        default:
            return 4;
    }
}

PlyHeader readHeader(const std::string& bytes, const std::string& path) {
    PlyHeader h;
    std::size_t pos = 0;
    bool formatSeen = false;
    for (;;) {
        const std::size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) throw InputError(fmt::format("{}: the PLY header has no end_header line", path));
        std::string line = bytes.substr(pos, end - pos);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        pos = end + 1;
        const std::string where = fmt::format("{}:{}", path, ++h.lines);
        std::istringstream in(line);
        std::string word;
        in >> word;
        if (h.lines == 1) {
            if (word != "ply") throw InputError(fmt::format("{}: not a PLY file (it does not start with 'ply')", path));
        } else if (word == "format") {
            std::string f;
            in >> f;
            if (f == "ascii") h.format = PlyHeader::Ascii;
            else if (f == "binary_little_endian") h.format = PlyHeader::BinaryLittle;
            else if (f == "binary_big_endian") h.format = PlyHeader::BinaryBig;
            else throw InputError(fmt::format("{}: unknown PLY format '{}'", where, f));
            formatSeen = true;
        } else if (word == "element") {
            PlyElement e;
            long long count = -1;
            in >> e.name >> count;
            if (!in || count < 0) throw InputError(fmt::format("{}: element '{}' needs a count of 0 or more", where, line));
            e.count = static_cast<std::uint64_t>(count);
            h.elements.push_back(e);
        } else if (word == "property") {
            if (h.elements.empty()) throw InputError(fmt::format("{}: property before any element", where));
            PlyProperty p;
            std::string type;
            in >> type;
            if (type == "list") {
                std::string countType, itemType;
                in >> countType >> itemType >> p.name;
                p.list = true;
                p.countType = plyType(countType, where);
                p.type = plyType(itemType, where);
            } else {
                p.type = plyType(type, where);
                in >> p.name;
            }
            if (p.name.empty()) throw InputError(fmt::format("{}: property without a name", where));
            h.elements.back().properties.push_back(p);
        } else if (word == "end_header") {
            break;
        } else if (word != "comment" && word != "obj_info" && !word.empty()) {
            throw InputError(fmt::format("{}: unknown PLY header line '{}'", where, line));
        }
    }
    if (!formatSeen) throw InputError(fmt::format("{}: the PLY header has no format line", path));
    h.dataStart = pos;
    return h;
}

/// Reads the values of the data section in order, as numbers, whatever the format.
class PlyReader {
public:
    PlyReader(const std::string& bytes, const PlyHeader& h, const std::string& path)
        : bytes_(bytes), pos_(h.dataStart), format_(h.format), path_(path), line_(h.lines) {
        if (format_ == PlyHeader::Ascii) nextLine();
    }

    double read(PlyType t, const std::string& what) {
        if (format_ == PlyHeader::Ascii) return readAscii(what);
        const int n = typeSize(t);
        if (pos_ + static_cast<std::size_t>(n) > bytes_.size())
            throw InputError(fmt::format("{}: the file ends inside {} (byte {})", path_, what, pos_));
        unsigned char b[8];
        std::memcpy(b, bytes_.data() + pos_, static_cast<std::size_t>(n));
        pos_ += static_cast<std::size_t>(n);
        if ((format_ == PlyHeader::BinaryBig) == (std::endian::native == std::endian::little))
            for (int i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
        return decode(t, b);
    }

    /// ASCII: the element ends at the end of its line.
    void endElement(const std::string& what) {
        if (format_ != PlyHeader::Ascii) return;
        std::string rest;
        if (lineStream_ >> rest) throw InputError(fmt::format("{}:{}: {} has more values than its properties ('{}')", path_, line_, what, rest));
        nextLine();
    }

private:
    static double decode(PlyType t, const unsigned char* b) {
        switch (t) {
            case PlyType::Int8: return static_cast<std::int8_t>(b[0]);
            case PlyType::Uint8: return b[0];
            case PlyType::Int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::Uint16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::Int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::Uint32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::Float32: { float v; std::memcpy(&v, b, 4); return v; }
            case PlyType::Float64: { double v; std::memcpy(&v, b, 8); return v; }
        }
        return 0;
    }

    double readAscii(const std::string& what) {
        std::string word;
        if (!(lineStream_ >> word)) throw InputError(fmt::format("{}:{}: {} has fewer values than its properties", path_, line_, what));
        char* end = nullptr;
        const double v = std::strtod(word.c_str(), &end);
        if (end == word.c_str() || *end) throw InputError(fmt::format("{}:{}: '{}' in {} is not a number", path_, line_, word, what));
        return v;
    }

    void nextLine() {
        for (;;) {
            if (pos_ >= bytes_.size()) {
                lineStream_ = std::istringstream();
                return;
            }
            const std::size_t end = std::min(bytes_.find('\n', pos_), bytes_.size());
            const std::string line = bytes_.substr(pos_, end - pos_);
            pos_ = end + 1;
            ++line_;
            if (line.find_first_not_of(" \t\r") == std::string::npos) continue;  // blank lines between elements
            lineStream_ = std::istringstream(line);
            return;
        }
    }

    const std::string& bytes_;
    std::size_t pos_;
    PlyHeader::Format format_;
    std::string path_;
    int line_;
    std::istringstream lineStream_;
};

/// A list's length or a vertex index as an integer: InputError unless it is a whole number of at most 2^40
/// in magnitude (a NaN or a float index would otherwise be undefined behaviour to convert).
std::int64_t integerValue(double v, const std::string& path, const std::string& what) {
    if (!(std::abs(v) <= 1099511627776.0) || v != std::floor(v))
        throw InputError(fmt::format("{}: {} has '{}' where a whole number belongs", path, what, v));
    return static_cast<std::int64_t>(v);
}

int propertyIndex(const PlyElement& e, std::initializer_list<const char*> names) {
    for (const char* n : names)
        for (std::size_t i = 0; i < e.properties.size(); ++i)
            if (e.properties[i].name == n && !e.properties[i].list) return static_cast<int>(i);
    return -1;
}

void readVertices(const PlyElement& e, PlyReader& r, const std::string& path, Scene& scene) {
    const int x = propertyIndex(e, {"x"}), y = propertyIndex(e, {"y"}), z = propertyIndex(e, {"z"});
    if (x < 0 || y < 0 || z < 0) throw InputError(fmt::format("{}: the vertex element has no x, y and z properties", path));
    const int nx = propertyIndex(e, {"nx"}), ny = propertyIndex(e, {"ny"}), nz = propertyIndex(e, {"nz"});
    const int u = propertyIndex(e, {"u", "s", "texture_u", "texture_s"}), v = propertyIndex(e, {"v", "t", "texture_v", "texture_t"});
    const bool normals = nx >= 0 && ny >= 0 && nz >= 0, uvs = u >= 0 && v >= 0;
    std::vector<double> values(e.properties.size());
    for (std::uint64_t i = 0; i < e.count; ++i) {
        const std::string what = fmt::format("vertex {} of {}", i, e.count);
        for (std::size_t p = 0; p < e.properties.size(); ++p) {
            const PlyProperty& prop = e.properties[p];
            if (!prop.list) {
                values[p] = r.read(prop.type, what);
                continue;
            }
            const std::int64_t n = integerValue(r.read(prop.countType, what), path, what);
            for (std::int64_t k = 0; k < n; ++k) r.read(prop.type, what);
        }
        r.endElement(what);
        const Vec3 pos(values[static_cast<std::size_t>(x)], values[static_cast<std::size_t>(y)], values[static_cast<std::size_t>(z)]);
        if (!isFinite(pos)) throw InputError(fmt::format("{}: {} is not finite", path, what));
        scene.positions.push_back(pos);
        if (normals) {
            const Vec3 n(values[static_cast<std::size_t>(nx)], values[static_cast<std::size_t>(ny)], values[static_cast<std::size_t>(nz)]);
            const double len = length(n);
            scene.normals.push_back(len > 0 && std::isfinite(len) ? n / len : Vec3(0, 0, 1));
        }
        if (uvs) {
            const double a = values[static_cast<std::size_t>(u)], b = values[static_cast<std::size_t>(v)];
            scene.uvs.push_back({std::isfinite(a) ? a : 0.0, std::isfinite(b) ? b : 0.0});
        }
    }
}

/// Appends triangle (a, b, c) of the vertices; false for a degenerate one (a repeated vertex).
bool addTriangle(Scene& scene, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (a == b || b == c || a == c) return false;
    Triangle t;
    t.v = {a, b, c};
    const bool normals = !scene.normals.empty(), uvs = !scene.uvs.empty();
    for (int k = 0; k < 3; ++k) {
        t.n[static_cast<std::size_t>(k)] = normals ? static_cast<std::int32_t>(t.v[static_cast<std::size_t>(k)]) : -1;
        t.t[static_cast<std::size_t>(k)] = uvs ? static_cast<std::int32_t>(t.v[static_cast<std::size_t>(k)]) : -1;
    }
    scene.triangles.push_back(t);
    return true;
}

/// A face or strip element's index lists; `strips`: triangle strips, else polygons. Returns the
/// triangles added and counts the zero-area ones dropped.
struct IndexCounts {
    std::uint64_t triangles = 0, degenerate = 0;
};

IndexCounts readIndexLists(const PlyElement& e, bool strips, PlyReader& r, const std::string& path, Scene& scene) {
    int list = -1;
    for (std::size_t i = 0; i < e.properties.size(); ++i)
        if (e.properties[i].list && (e.properties[i].name == "vertex_indices" || e.properties[i].name == "vertex_index")) list = static_cast<int>(i);
    if (list < 0) throw InputError(fmt::format("{}: element '{}' has no vertex_indices list", path, e.name));
    const auto vertexCount = static_cast<std::int64_t>(scene.positions.size());
    IndexCounts counts;
    std::vector<std::int64_t> idx;
    for (std::uint64_t i = 0; i < e.count; ++i) {
        const std::string what = fmt::format("{} {} of {}", e.name, i, e.count);
        for (std::size_t p = 0; p < e.properties.size(); ++p) {
            const PlyProperty& prop = e.properties[p];
            if (!prop.list) {
                r.read(prop.type, what);
                continue;
            }
            const std::int64_t n = integerValue(r.read(prop.countType, what), path, what);
            if (n < 0) throw InputError(fmt::format("{}: {} has a negative length", path, what));
            if (static_cast<int>(p) == list) idx.clear();
            for (std::int64_t k = 0; k < n; ++k) {
                const std::int64_t v = integerValue(r.read(prop.type, what), path, what);
                if (static_cast<int>(p) != list) continue;
                if (v >= vertexCount || v < (strips ? -1 : 0))
                    throw InputError(fmt::format("{}: {} has vertex index {} (the file has {} vertices)", path, what, v, vertexCount));
                idx.push_back(v);
            }
        }
        r.endElement(what);
        const auto add = [&](std::int64_t a, std::int64_t b, std::int64_t c) {
            if (addTriangle(scene, static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(c)))
                ++counts.triangles;
            else
                ++counts.degenerate;
        };
        if (!strips) {
            if (idx.size() < 3) ++counts.degenerate;
            for (std::size_t k = 2; k < idx.size(); ++k) add(idx[0], idx[k - 1], idx[k]);  // a fan
            continue;
        }
        std::size_t start = 0;  // triangle strips: -1 restarts; odd triangles reversed to keep the winding
        for (std::size_t k = 0; k < idx.size(); ++k) {
            if (idx[k] < 0) {
                start = k + 1;
                continue;
            }
            if (k < start + 2) continue;
            if ((k - start) % 2 == 0) add(idx[k - 2], idx[k - 1], idx[k]);
            else add(idx[k - 1], idx[k - 2], idx[k]);
        }
    }
    return counts;
}

void skipElement(const PlyElement& e, PlyReader& r, const std::string& path) {
    if (e.properties.empty()) return;  // nothing stored, however many it declares
    for (std::uint64_t i = 0; i < e.count; ++i) {
        const std::string what = fmt::format("{} {} of {}", e.name, i, e.count);
        for (const PlyProperty& prop : e.properties) {
            const std::int64_t n = prop.list ? integerValue(r.read(prop.countType, what), path, what) : 1;
            for (std::int64_t k = 0; k < n; ++k) r.read(prop.type, what);
        }
        r.endElement(what);
    }
}

}  // namespace

Scene loadPly(const std::string& path) {
    if (!std::filesystem::exists(path)) throw MissingFileError(fmt::format("{}: no such file", path));
    const std::string bytes = readTextFile(path);  // the whole file, binary data included
    const PlyHeader h = readHeader(bytes, path);
    Scene scene;
    scene.name = std::filesystem::path(path).stem().string();
    scene.materials.push_back(PhongMaterial{});
    PlyReader reader(bytes, h, path);
    std::uint64_t declaredFaces = 0;
    IndexCounts faces;
    for (const PlyElement& e : h.elements) {
        if (e.name == "vertex") {
            requireMemory(saturatingMultiply(e.count, 80), fmt::format("{}: {} vertices", path, e.count));
            readVertices(e, reader, path, scene);
        } else if (e.name == "face" || e.name == "tristrips") {
            if (scene.positions.empty() && e.count > 0)
                throw InputError(fmt::format("{}: element '{}' comes before any vertex", path, e.name));
            requireMemory(saturatingMultiply(e.count, 48), fmt::format("{}: {} {}", path, e.count, e.name));
            const bool isStrip = e.name == "tristrips";
            const IndexCounts c = readIndexLists(e, isStrip, reader, path, scene);
            if (!isStrip) declaredFaces += e.count, faces.triangles += c.triangles, faces.degenerate += c.degenerate;
        } else {
            skipElement(e, reader, path);
        }
    }
    if (scene.triangles.empty()) throw InputError(fmt::format("{}: no triangles in the file", path));
    if (faces.degenerate > 0)
        scene.warnings.push_back(fmt::format("{}: {} of its {} faces have fewer than 3 distinct vertices (no area) and were left out",
                                             path, faces.degenerate, declaredFaces));
    scene.camera = scene.automaticCamera();
    return scene;
}

}  // namespace symphong
