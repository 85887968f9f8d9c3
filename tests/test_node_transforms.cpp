// Files whose nodes nest place their meshes by the whole chain of transforms (parent x child), in glTF,
// Collada and (ASCII) FBX written by hand: a triangle under a child node (scaled, rotated, translated) under a
// translated parent, its loaded vertices against the product of the matrices written out here.
#include "test_util.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

using namespace symphong;

namespace {

std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const unsigned v = bytes[i] << 16 | (i + 1 < bytes.size() ? bytes[i + 1] << 8 : 0) | (i + 2 < bytes.size() ? bytes[i + 2] : 0);
        out += table[v >> 18 & 63];
        out += table[v >> 12 & 63];
        out += i + 1 < bytes.size() ? table[v >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
}

// The triangle in its mesh's own coordinates.
const Vec3 kTriangle[3] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};

/// parent: translate (10, 0, 0); child: translate (0, 5, 0), rotate 90 degrees about +z, scale 2:
/// world = T(10,0,0) T(0,5,0) Rz(90) S(2) v; Rz(90) (x, y, z) = (-y, x, z).
Vec3 expectedWorld(const Vec3& v) { return Vec3(10 - 2 * v.y, 5 + 2 * v.x, 2 * v.z); }

void expectPlaced(const Scene& s, const std::string& what) {
    ASSERT_EQ(s.triangles.size(), 1u) << what;
    for (int k = 0; k < 3; ++k) {
        const Vec3 p = s.positions[s.triangles[0].v[static_cast<std::size_t>(k)]];
        bool found = false;
        for (const Vec3& v : kTriangle) found = found || length(p - expectedWorld(v)) < 1e-5;
        EXPECT_TRUE(found) << what << ": vertex " << k << " at (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
}

}  // namespace

TEST(NodeTransforms, GltfChildNodesAreTransformedByTheirParents) {
    test::TempDir dir;
    std::vector<unsigned char> buffer(3 * 3 * sizeof(float) + 3 * sizeof(std::uint16_t) + 2);
    float* xyz = reinterpret_cast<float*>(buffer.data());
    for (int k = 0; k < 3; ++k) xyz[3 * k] = static_cast<float>(kTriangle[k].x), xyz[3 * k + 1] = static_cast<float>(kTriangle[k].y),
                                xyz[3 * k + 2] = static_cast<float>(kTriangle[k].z);
    const std::uint16_t indices[3] = {0, 1, 2};
    std::memcpy(buffer.data() + 36, indices, sizeof indices);
    const double s = std::sqrt(0.5);  // quaternion of 90 degrees about +z: (0, 0, sin 45, cos 45)
    const std::string gltf = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [{"name": "parent", "translation": [10, 0, 0], "children": [1]},
                {"name": "child", "translation": [0, 5, 0], "rotation": [0, 0, )" + std::to_string(s) + ", " + std::to_string(s) +
                             R"(], "scale": [2, 2, 2], "mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                    {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
      "buffers": [{"byteLength": )" + std::to_string(buffer.size()) +
                             R"(, "uri": "data:application/octet-stream;base64,)" + base64(buffer) + R"("}]})";
    dir.write("nested.gltf", gltf);
    expectPlaced(loadScene(dir.file("nested.gltf")), "glTF");
}

TEST(NodeTransforms, ColladaChildNodesAreTransformedByTheirParents) {
    test::TempDir dir;
    dir.write("nested.dae", R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tri" name="tri"><mesh>
      <source id="tri-pos"><float_array id="tri-pos-array" count="9">0 0 0 1 0 0 0 1 0</float_array>
        <technique_common><accessor source="#tri-pos-array" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
      <vertices id="tri-vtx"><input semantic="POSITION" source="#tri-pos"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#tri-vtx" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene">
      <node id="parent" name="parent"><translate>10 0 0</translate>
        <node id="child" name="child"><translate>0 5 0</translate><rotate>0 0 1 90</rotate><scale>2 2 2</scale>
          <instance_geometry url="#tri"/>
        </node>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)");
    expectPlaced(loadScene(dir.file("nested.dae")), "Collada");
}

// FBX 7.4 in its ASCII form, the least a reader needs: two Models connected child -> parent -> root, the
// geometry connected to the child. A Model's transform with no pivots or offsets is T R S (FBX's
// default rotation order XYZ; only z turns here); Lcl Rotation is in degrees.
TEST(NodeTransforms, FbxChildModelsAreTransformedByTheirParents) {
    test::TempDir dir;
    const auto model = [](long id, const char* name, const char* props) {
        return "\tModel: " + std::to_string(id) + ", \"Model::" + name + "\", \"Mesh\" {\n\t\tVersion: 232\n" +
               "\t\tProperties70:  {\n" + props + "\t\t}\n\t\tShading: T\n\t\tCulling: \"CullingOff\"\n\t}\n";
    };
    std::string fbx = R"(; FBX 7.4.0 project file
FBXHeaderExtension:  {
	FBXHeaderVersion: 1003
	FBXVersion: 7400
	Creator: "symphong tests/test_node_transforms.cpp"
}
GlobalSettings:  {
	Version: 1000
	Properties70:  {
		P: "UpAxis", "int", "Integer", "",1
		P: "UpAxisSign", "int", "Integer", "",1
		P: "FrontAxis", "int", "Integer", "",2
		P: "FrontAxisSign", "int", "Integer", "",1
		P: "CoordAxis", "int", "Integer", "",0
		P: "CoordAxisSign", "int", "Integer", "",1
		P: "UnitScaleFactor", "double", "Number", "",100
	}
}
Objects:  {
	Geometry: 3000, "Geometry::Tri", "Mesh" {
		Vertices: *9 {
			a: 0,0,0,1,0,0,0,1,0
		}
		PolygonVertexIndex: *3 {
			a: 0,1,-3
		}
		GeometryVersion: 124
	}
)";
    fbx += model(1000, "Parent", "\t\t\tP: \"Lcl Translation\", \"Lcl Translation\", \"\", \"A\",10,0,0\n");
    fbx += model(2000, "Child",
                 "\t\t\tP: \"Lcl Translation\", \"Lcl Translation\", \"\", \"A\",0,5,0\n"
                 "\t\t\tP: \"Lcl Rotation\", \"Lcl Rotation\", \"\", \"A\",0,0,90\n"
                 "\t\t\tP: \"Lcl Scaling\", \"Lcl Scaling\", \"\", \"A\",2,2,2\n");
    fbx += R"(}
Connections:  {
	C: "OO",1000,0
	C: "OO",2000,1000
	C: "OO",3000,2000
}
)";
    dir.write("nested.fbx", fbx);
    expectPlaced(loadScene(dir.file("nested.fbx")), "FBX");
}
