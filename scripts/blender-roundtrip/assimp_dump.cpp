// assimp_dump.cpp — prints what Assimp (Debian 12: 5.2.5) makes of a file, with the import flags of
// symphong's loader (src/scene/assimp_loader.cpp, loadAssimp): every material property (key, semantic,
// index, type, value), every camera's fields and its node's world transform, every light, every mesh's
// vertex / face counts (and face sizes), the scene metadata (FBX units and axes, Collada's) and the node
// tree with its transforms.
//
// Not part of the build. Compile by hand:
//     g++ -std=c++17 -O1 -o assimp_dump scripts/blender-roundtrip/assimp_dump.cpp -lassimp
// Run:
//     ./assimp_dump FILE           # symphong's flags (Triangulate | SortByPType | JoinIdenticalVertices |
//                                  #   ValidateDataStructure; src/scene/assimp_guard.cpp). The dumps in
//                                  #   tests/data/blender/assimp-5.2 were made with FindInvalidData and
//                                  #   points and lines removed, as symphong read files then.
//     ./assimp_dump --raw FILE     # no post-processing at all (faces as the importer made them)
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/metadata.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/version.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

const char* typeName(aiPropertyTypeInfo t) {
    switch (t) {
        case aiPTI_Float: return "float";
        case aiPTI_Double: return "double";
        case aiPTI_String: return "string";
        case aiPTI_Integer: return "int";
        case aiPTI_Buffer: return "buffer";
        default: return "?";
    }
}

const char* textureTypeName(unsigned t) {
    switch (t) {
        case aiTextureType_NONE: return "NONE";
        case aiTextureType_DIFFUSE: return "DIFFUSE";
        case aiTextureType_SPECULAR: return "SPECULAR";
        case aiTextureType_AMBIENT: return "AMBIENT";
        case aiTextureType_EMISSIVE: return "EMISSIVE";
        case aiTextureType_HEIGHT: return "HEIGHT";
        case aiTextureType_NORMALS: return "NORMALS";
        case aiTextureType_SHININESS: return "SHININESS";
        case aiTextureType_OPACITY: return "OPACITY";
        case aiTextureType_DISPLACEMENT: return "DISPLACEMENT";
        case aiTextureType_LIGHTMAP: return "LIGHTMAP";
        case aiTextureType_REFLECTION: return "REFLECTION";
        case aiTextureType_BASE_COLOR: return "BASE_COLOR";
        case aiTextureType_NORMAL_CAMERA: return "NORMAL_CAMERA";
        case aiTextureType_EMISSION_COLOR: return "EMISSION_COLOR";
        case aiTextureType_METALNESS: return "METALNESS";
        case aiTextureType_DIFFUSE_ROUGHNESS: return "DIFFUSE_ROUGHNESS";
        case aiTextureType_AMBIENT_OCCLUSION: return "AMBIENT_OCCLUSION";
        case aiTextureType_SHEEN: return "SHEEN";
        case aiTextureType_CLEARCOAT: return "CLEARCOAT";
        case aiTextureType_TRANSMISSION: return "TRANSMISSION";
        case aiTextureType_UNKNOWN: return "UNKNOWN";
        default: return "?";
    }
}

void printProperty(const aiMaterialProperty& p) {
    std::printf("    %-36s semantic %u (%s) index %u  %-6s len %3u = ", p.mKey.C_Str(), p.mSemantic, textureTypeName(p.mSemantic), p.mIndex,
                typeName(p.mType), p.mDataLength);
    switch (p.mType) {
        case aiPTI_Float: {
            const std::size_t n = p.mDataLength / sizeof(float);
            for (std::size_t i = 0; i < n; ++i) {
                float v;
                std::memcpy(&v, p.mData + i * sizeof(float), sizeof v);
                std::printf("%s%.9g", i ? " " : "", v);
            }
            break;
        }
        case aiPTI_Double: {
            const std::size_t n = p.mDataLength / sizeof(double);
            for (std::size_t i = 0; i < n; ++i) {
                double v;
                std::memcpy(&v, p.mData + i * sizeof(double), sizeof v);
                std::printf("%s%.17g", i ? " " : "", v);
            }
            break;
        }
        case aiPTI_Integer: {
            const std::size_t n = p.mDataLength / sizeof(int);
            for (std::size_t i = 0; i < n; ++i) {
                int v;
                std::memcpy(&v, p.mData + i * sizeof(int), sizeof v);
                std::printf("%s%d", i ? " " : "", v);
            }
            break;
        }
        case aiPTI_String: {
            // uint32 length, then the characters and a terminating zero.
            std::uint32_t len = 0;
            if (p.mDataLength >= 4) std::memcpy(&len, p.mData, 4);
            if (len > p.mDataLength - 4) len = p.mDataLength - 4;
            std::printf("\"%.*s\"", static_cast<int>(len), p.mData + 4);
            break;
        }
        default: {
            std::printf("0x");
            for (unsigned i = 0; i < p.mDataLength && i < 32; ++i) std::printf("%02x", static_cast<unsigned char>(p.mData[i]));
            if (p.mDataLength > 32) std::printf("...");
            // A buffer of 4-byte floats or ints is common (e.g. $mat.blend.*): show both readings.
            if (p.mDataLength % 4 == 0 && p.mDataLength <= 64) {
                std::printf("  (as floats:");
                for (unsigned i = 0; i < p.mDataLength; i += 4) {
                    float v;
                    std::memcpy(&v, p.mData + i, 4);
                    std::printf(" %.9g", v);
                }
                std::printf(")");
            }
        }
    }
    std::printf("\n");
}

void printMatrix(const char* indent, const aiMatrix4x4& m) {
    std::printf("%s[%10.6f %10.6f %10.6f %10.6f]\n", indent, m.a1, m.a2, m.a3, m.a4);
    std::printf("%s[%10.6f %10.6f %10.6f %10.6f]\n", indent, m.b1, m.b2, m.b3, m.b4);
    std::printf("%s[%10.6f %10.6f %10.6f %10.6f]\n", indent, m.c1, m.c2, m.c3, m.c4);
    std::printf("%s[%10.6f %10.6f %10.6f %10.6f]\n", indent, m.d1, m.d2, m.d3, m.d4);
}

void printMetadata(const aiMetadata* md, const char* indent) {
    if (!md) return;
    for (unsigned i = 0; i < md->mNumProperties; ++i) {
        const aiMetadataEntry& e = md->mValues[i];
        std::printf("%s%s = ", indent, md->mKeys[i].C_Str());
        switch (e.mType) {
            case AI_BOOL: std::printf("%s (bool)\n", *static_cast<bool*>(e.mData) ? "true" : "false"); break;
            case AI_INT32: std::printf("%d (int32)\n", *static_cast<int32_t*>(e.mData)); break;
            case AI_UINT64: std::printf("%llu (uint64)\n", static_cast<unsigned long long>(*static_cast<uint64_t*>(e.mData))); break;
            case AI_FLOAT: std::printf("%.9g (float)\n", *static_cast<float*>(e.mData)); break;
            case AI_DOUBLE: std::printf("%.17g (double)\n", *static_cast<double*>(e.mData)); break;
            case AI_AISTRING: std::printf("\"%s\" (string)\n", static_cast<aiString*>(e.mData)->C_Str()); break;
            case AI_AIVECTOR3D: {
                const aiVector3D& v = *static_cast<aiVector3D*>(e.mData);
                std::printf("(%g, %g, %g) (vector)\n", v.x, v.y, v.z);
                break;
            }
            case AI_AIMETADATA: std::printf("(metadata)\n"); printMetadata(static_cast<aiMetadata*>(e.mData), "      "); break;
            default: std::printf("(type %d)\n", static_cast<int>(e.mType));
        }
    }
}

struct Placed {
    const aiNode* node;
    aiMatrix4x4 world;
    int depth;
};

std::vector<Placed> walk(const aiNode* root) {
    std::vector<Placed> out, stack{{root, root->mTransformation, 0}};
    while (!stack.empty()) {
        Placed p = stack.back();
        stack.pop_back();
        out.push_back(p);
        for (unsigned i = p.node->mNumChildren; i-- > 0;)
            stack.push_back({p.node->mChildren[i], p.world * p.node->mChildren[i]->mTransformation, p.depth + 1});
    }
    return out;
}

aiMatrix4x4 worldOf(const std::vector<Placed>& nodes, const aiString& name) {
    for (const auto& p : nodes)
        if (std::strcmp(p.node->mName.C_Str(), name.C_Str()) == 0) return p.world;
    return aiMatrix4x4();
}

aiVector3D normalized(aiVector3D v) {
    const float l = v.Length();
    return l > 0 ? v / l : v;
}

}  // namespace

int main(int argc, char** argv) {
    bool raw = false;
    const char* path = nullptr;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--raw") == 0)
            raw = true;
        else
            path = argv[i];
    }
    if (!path) {
        std::fprintf(stderr, "usage: %s [--raw] FILE\n", argv[0]);
        return 2;
    }
    Assimp::Importer importer;
    unsigned flags = 0;
    if (!raw) {
        flags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure;
    }
    const aiScene* s = importer.ReadFile(path, flags);
    std::printf("file: %s\nassimp: %u.%u.%u   post-processing: %s\n", path, aiGetVersionMajor(), aiGetVersionMinor(), aiGetVersionPatch(),
                raw ? "none (--raw)" : "symphong's (Triangulate|SortByPType|JoinIdenticalVertices|ValidateDataStructure)");
    if (!s) {
        std::printf("IMPORT FAILED: %s\n", importer.GetErrorString());
        return 1;
    }
    std::printf("scene flags: 0x%x%s\n", s->mFlags, (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE) ? " (INCOMPLETE)" : "");

    std::printf("\n== metadata\n");
    printMetadata(s->mMetaData, "  ");

    const std::vector<Placed> nodes = walk(s->mRootNode);
    std::printf("\n== nodes (%zu)\n", nodes.size());
    for (const auto& p : nodes) {
        std::printf("%*s- '%s'  meshes:", 2 * p.depth + 2, "", p.node->mName.C_Str());
        for (unsigned k = 0; k < p.node->mNumMeshes; ++k) std::printf(" %u", p.node->mMeshes[k]);
        std::printf("\n");
        const aiMatrix4x4& m = p.node->mTransformation;
        if (!m.IsIdentity()) {
            std::printf("%*s  local transform:\n", 2 * p.depth + 2, "");
            printMatrix(std::string(2 * p.depth + 6, ' ').c_str(), m);
        }
        if (p.node->mMetaData && p.node->mMetaData->mNumProperties > 0 && p.depth <= 1) {
            std::printf("%*s  metadata:\n", 2 * p.depth + 2, "");
            printMetadata(p.node->mMetaData, std::string(2 * p.depth + 6, ' ').c_str());
        }
    }

    std::printf("\n== materials (%u)\n", s->mNumMaterials);
    for (unsigned i = 0; i < s->mNumMaterials; ++i) {
        const aiMaterial* m = s->mMaterials[i];
        aiString name;
        m->Get(AI_MATKEY_NAME, name);
        std::printf("  material %u '%s' (%u properties)\n", i, name.C_Str(), m->mNumProperties);
        for (unsigned k = 0; k < m->mNumProperties; ++k) printProperty(*m->mProperties[k]);
        for (unsigned t = aiTextureType_NONE; t <= AI_TEXTURE_TYPE_MAX; ++t) {
            const auto type = static_cast<aiTextureType>(t);
            for (unsigned k = 0; k < m->GetTextureCount(type); ++k) {
                aiString file;
                aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
                unsigned uv = 0;
                m->GetTexture(type, k, &file, nullptr, &uv, nullptr, nullptr, modes);
                std::printf("    texture %s[%u]: '%s' uv %u wrap %d %d%s\n", textureTypeName(t), k, file.C_Str(), uv, modes[0], modes[1],
                            s->GetEmbeddedTexture(file.C_Str()) ? " (embedded)" : "");
            }
        }
    }

    std::printf("\n== meshes (%u)\n", s->mNumMeshes);
    unsigned long long totalV = 0, totalF = 0, totalTri = 0;
    aiVector3D lo(1e30f, 1e30f, 1e30f), hi(-1e30f, -1e30f, -1e30f);
    for (const auto& p : nodes)
        for (unsigned k = 0; k < p.node->mNumMeshes; ++k) {
            const aiMesh* mesh = s->mMeshes[p.node->mMeshes[k]];
            for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
                const aiVector3D w = p.world * mesh->mVertices[v];
                lo.x = std::min(lo.x, w.x), lo.y = std::min(lo.y, w.y), lo.z = std::min(lo.z, w.z);
                hi.x = std::max(hi.x, w.x), hi.y = std::max(hi.y, w.y), hi.z = std::max(hi.z, w.z);
            }
        }
    for (unsigned i = 0; i < s->mNumMeshes; ++i) {
        const aiMesh* mesh = s->mMeshes[i];
        std::map<unsigned, unsigned> sizes;
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) ++sizes[mesh->mFaces[f].mNumIndices];
        std::printf("  mesh %u '%s': %u vertices, %u faces (", i, mesh->mName.C_Str(), mesh->mNumVertices, mesh->mNumFaces);
        bool first = true;
        for (const auto& [n, c] : sizes) std::printf("%s%u of %u", first ? "" : ", ", c, n), first = false;
        std::printf("), material %u, primitive types 0x%x, normals %s, tangents %s, uv channels", mesh->mMaterialIndex, mesh->mPrimitiveTypes,
                    mesh->mNormals ? "yes" : "no", mesh->mTangents ? "yes" : "no");
        for (unsigned c = 0; c < AI_MAX_NUMBER_OF_TEXTURECOORDS; ++c)
            if (mesh->mTextureCoords[c]) std::printf(" %u(%ud)", c, mesh->mNumUVComponents[c]);
        std::printf(", colour sets");
        for (unsigned c = 0; c < AI_MAX_NUMBER_OF_COLOR_SETS; ++c)
            if (mesh->mColors[c]) std::printf(" %u", c);
        std::printf("\n");
        totalV += mesh->mNumVertices;
        totalF += mesh->mNumFaces;
        if (sizes.count(3)) totalTri += sizes[3];
    }
    std::printf("  total: %llu vertices, %llu faces, %llu triangles; world bounds (%g, %g, %g) - (%g, %g, %g)\n", totalV, totalF, totalTri, lo.x,
                lo.y, lo.z, hi.x, hi.y, hi.z);

    std::printf("\n== cameras (%u)\n", s->mNumCameras);
    for (unsigned i = 0; i < s->mNumCameras; ++i) {
        const aiCamera& c = *s->mCameras[i];
        std::printf("  camera %u '%s'\n", i, c.mName.C_Str());
        std::printf("    mHorizontalFOV  = %.9g rad = %.6f deg (2x = %.6f deg)\n", c.mHorizontalFOV, c.mHorizontalFOV * kDeg,
                    2 * c.mHorizontalFOV * kDeg);
        std::printf("    mAspect         = %.9g\n", c.mAspect);
        std::printf("    mClipPlaneNear  = %.9g, mClipPlaneFar = %.9g, mOrthographicWidth = %.9g\n", c.mClipPlaneNear, c.mClipPlaneFar,
                    c.mOrthographicWidth);
        std::printf("    mPosition       = (%.6f, %.6f, %.6f)\n", c.mPosition.x, c.mPosition.y, c.mPosition.z);
        std::printf("    mLookAt         = (%.6f, %.6f, %.6f)\n", c.mLookAt.x, c.mLookAt.y, c.mLookAt.z);
        std::printf("    mUp             = (%.6f, %.6f, %.6f)\n", c.mUp.x, c.mUp.y, c.mUp.z);
        const aiMatrix4x4 world = worldOf(nodes, c.mName);
        aiMatrix3x3 rot(world);
        const aiVector3D pos = world * c.mPosition, look = normalized(rot * c.mLookAt), up = normalized(rot * c.mUp);
        std::printf("    node world transform:\n");
        printMatrix("      ", world);
        std::printf("    in world: position (%.6f, %.6f, %.6f), looks along (%.6f, %.6f, %.6f), up (%.6f, %.6f, %.6f)\n", pos.x, pos.y, pos.z,
                    look.x, look.y, look.z, up.x, up.y, up.z);
        const double aspect = c.mAspect > 0 ? c.mAspect : 1.0;
        std::printf("    vertical FOV if mHorizontalFOV is the half-angle: %.6f deg; if it is the full angle: %.6f deg (aspect %.6f)\n",
                    2 * std::atan(std::tan(c.mHorizontalFOV) / aspect) * kDeg, 2 * std::atan(std::tan(c.mHorizontalFOV / 2) / aspect) * kDeg,
                    aspect);
    }

    std::printf("\n== lights (%u)\n", s->mNumLights);
    for (unsigned i = 0; i < s->mNumLights; ++i) {
        const aiLight& l = *s->mLights[i];
        std::printf("  light %u '%s' type %d colour diffuse (%g, %g, %g) specular (%g, %g, %g) attenuation %g %g %g cones %g %g deg\n", i,
                    l.mName.C_Str(), static_cast<int>(l.mType), l.mColorDiffuse.r, l.mColorDiffuse.g, l.mColorDiffuse.b, l.mColorSpecular.r,
                    l.mColorSpecular.g, l.mColorSpecular.b, l.mAttenuationConstant, l.mAttenuationLinear, l.mAttenuationQuadratic,
                    l.mAngleInnerCone * kDeg, l.mAngleOuterCone * kDeg);
    }
    std::printf("\n== embedded textures (%u)\n", s->mNumTextures);
    for (unsigned i = 0; i < s->mNumTextures; ++i) {
        const aiTexture& t = *s->mTextures[i];
        std::printf("  texture %u '%s': %u x %u, hint '%s'\n", i, t.mFilename.C_Str(), t.mWidth, t.mHeight, t.achFormatHint);
    }
    return 0;
}
