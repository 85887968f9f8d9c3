// scene/ply_loader.cpp: PLY faces and triangle strips read in full (ASCII, binary in both byte orders),
// the strips' winding kept, normals and texture coordinates, the neutral default material without a
// warning about it, and refusals naming what is wrong.
#include "io/files.h"
#include "io/input_error.h"
#include "scene/scene.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>

namespace symphong {
namespace {

using test::TempDir;

/// The geometric normal of triangle t.
Vec3 faceNormal(const Scene& s, const Triangle& t) {
    return normalize(cross(s.positions[t.v[1]] - s.positions[t.v[0]], s.positions[t.v[2]] - s.positions[t.v[0]]));
}

/// A grid of (n + 1) x (n + 1) vertices in the z = 0 plane as one triangle strip per row, each ended by
/// -1: 2 n triangles per row, all facing +z. Written as ASCII, or binary in either byte order.
std::string gridPly(const TempDir& dir, const std::string& name, int n, const std::string& format) {
    std::string header = "ply\nformat " + format + " 1.0\ncomment a grid of strips\nelement vertex " + std::to_string((n + 1) * (n + 1)) +
                         "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement tristrips 1\n"
                         "property list int int vertex_indices\nend_header\n";
    std::vector<int> strip;
    for (int row = 0; row < n; ++row) {
        for (int col = 0; col <= n; ++col) {
            strip.push_back((row + 1) * (n + 1) + col);  // upper, then lower: counter-clockwise seen from +z
            strip.push_back(row * (n + 1) + col);
        }
        strip.push_back(-1);
    }
    std::ofstream out(dir.file(name), std::ios::binary);
    out << header;
    const bool big = format == "binary_big_endian";
    const auto put = [&](const void* p, int size) {
        unsigned char b[4];
        std::memcpy(b, p, static_cast<std::size_t>(size));
        if (big) std::reverse(b, b + size);
        out.write(reinterpret_cast<const char*>(b), size);
    };
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) {
            const float v[3] = {static_cast<float>(x), static_cast<float>(y), 0.0f};
            const unsigned char red = 200;
            if (format == "ascii") {
                out << v[0] << " " << v[1] << " " << v[2] << " 200\n";
            } else {
                for (float f : v) put(&f, 4);
                put(&red, 1);
            }
        }
    const int count = static_cast<int>(strip.size());
    if (format == "ascii") {
        out << count;
        for (int i : strip) out << " " << i;
        out << "\n";
    } else {
        put(&count, 4);
        for (int i : strip) put(&i, 4);
    }
    return dir.file(name);
}

TEST(Ply, TriangleStripsLoadInFullWithTheirWinding) {
    TempDir dir;
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        const Scene s = loadScene(gridPly(dir, std::string(format) + ".ply", 20, format));
        ASSERT_EQ(s.positions.size(), 21u * 21u) << format;
        ASSERT_EQ(s.triangles.size(), 2u * 20u * 20u) << format;  // every triangle of every strip
        for (const Triangle& t : s.triangles) ASSERT_NEAR(faceNormal(s, t).z, 1.0, 1e-12) << format;
        for (const std::string& w : s.warnings) EXPECT_EQ(w.find("reflects more"), std::string::npos) << w;  // Assimp's default did
        ASSERT_EQ(s.materials.size(), 1u);
        EXPECT_EQ(s.materials[0].rhoD.x, PhongMaterial{}.rhoD.x);  // the neutral default of an OBJ without MTL
        EXPECT_EQ(s.materials[0].rhoS.x, 0.0);
    }
}

TEST(Ply, PolygonsAreFannedAndNormalsAndUvsRead) {
    TempDir dir;
    const std::string path = dir.write("q.ply",
                                       "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                                       "property float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n"
                                       "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
                                       "0 0 0 0 0 2 0 0\n1 0 0 0 0 2 1 0\n1 1 0 0 0 2 1 1\n0 1 0 0 0 2 0 1\n2 0 0 0 0 1 0.5 0.5\n"
                                       "4 0 1 2 3\n3 1 4 2\n");
    const Scene s = loadScene(path);
    ASSERT_EQ(s.triangles.size(), 3u);
    ASSERT_EQ(s.normals.size(), 5u);
    EXPECT_DOUBLE_EQ(s.normals[0].z, 1.0);  // normalised
    ASSERT_EQ(s.uvs.size(), 5u);
    EXPECT_DOUBLE_EQ(s.uvs[2][1], 1.0);
    EXPECT_EQ(s.triangles[1].t[2], 3);
    EXPECT_EQ(s.triangles[2].n[1], 4);
}

TEST(Ply, IncompleteOrWrongFilesAreRefusedNamingWhat) {
    TempDir dir;
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::pair<const char*, const char*> cases[] = {
        {"0 0 0\n1 0 0\n", "fewer values"},                     // the file ends inside a vertex
        {"0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "vertex index 7"},   // an index out of range
        {"0 0 0\n1 0 0\n0 1 0\n3 0 1 x\n", "'x'"},              // not a number
        {"0 0 0\n1 0 0\n0 1 0 5\n3 0 1 2\n", "more values"},    // a vertex with a value too many
    };
    for (const auto& [body, message] : cases) {
        const std::string path = dir.write("bad.ply", head + body);
        try {
            loadScene(path);
            ADD_FAILURE() << body << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("bad.ply"), std::string::npos) << e.what();
        }
    }
    std::string binary = gridPly(dir, "cut.ply", 4, "binary_little_endian");
    std::string bytes = readTextFile(binary);
    std::ofstream(binary, std::ios::binary) << bytes.substr(0, bytes.size() - 10);
    EXPECT_THROW(loadScene(binary), InputError);
    EXPECT_THROW(loadScene(dir.write("x.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n")), InputError);
    EXPECT_THROW(loadScene(dir.write("y.ply", "plx\n")), InputError);
}

}  // namespace
}  // namespace symphong
