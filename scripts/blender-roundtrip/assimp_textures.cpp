// What Assimp reads of a file's textures, tangent frames and cameras (a companion of
// scripts/blender-roundtrip/assimp_dump.cpp, for tests/data/blender/normalmap and portrait).
//
//   g++ -std=c++17 -O1 -o /tmp/assimp_textures assimp_textures.cpp -lassimp
//   /tmp/assimp_textures [--calc-tangents] [--no-find-invalid-data] FILE
//
// Import flags: symphong's (Triangulate | SortByPType | JoinIdenticalVertices | ValidateDataStructure |
// FindInvalidData), plus CalcTangentSpace with --calc-tangents, less FindInvalidData with
// --no-find-invalid-data (FindInvalidData deletes a mesh's tangents and bitangents when all its tangents are
// equal, e.g. on a flat plane).
// Prints per material: the texture count of every aiTextureType, each texture's path, mapping, uv index,
// blend factor and every property stored under that texture's semantic ($tex.*, e.g. glTF's
// $tex.scale); per mesh: normals / tangents / bitangents present, and per vertex (the first 8) the
// position, normal, tangent, bitangent, uv (Assimp's, v flipped back for glTF), the handedness
// sign(dot(cross(N, T), B)), and the same frame in world space (node transforms applied, normalized);
// per camera: the aiCamera fields.
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/version.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

const double kDeg = 180.0 / 3.14159265358979323846;

const char* textureTypeName(unsigned t) {
    static const char* names[] = {"NONE",      "DIFFUSE",       "SPECULAR",       "AMBIENT",         "EMISSIVE",          "HEIGHT",
                                  "NORMALS",   "SHININESS",     "OPACITY",        "DISPLACEMENT",    "LIGHTMAP",          "REFLECTION",
                                  "BASE_COLOR", "NORMAL_CAMERA", "EMISSION_COLOR", "METALNESS",       "DIFFUSE_ROUGHNESS", "AMBIENT_OCCLUSION",
                                  "SHEEN",     "CLEARCOAT",     "TRANSMISSION"};
    if (t < sizeof names / sizeof *names) return names[t];
    if (t == aiTextureType_UNKNOWN) return "UNKNOWN";
    return "?";
}

std::string value(const aiMaterialProperty& p) {
    char buf[128];
    std::string out;
    switch (p.mType) {
        case aiPTI_Float:
            for (unsigned i = 0; i < p.mDataLength / 4; ++i) {
                float v;
                std::memcpy(&v, p.mData + 4 * i, 4);
                std::snprintf(buf, sizeof buf, "%s%.9g", i ? " " : "", v);
                out += buf;
            }
            return "float " + out;
        case aiPTI_Double:
            for (unsigned i = 0; i < p.mDataLength / 8; ++i) {
                double v;
                std::memcpy(&v, p.mData + 8 * i, 8);
                std::snprintf(buf, sizeof buf, "%s%.17g", i ? " " : "", v);
                out += buf;
            }
            return "double " + out;
        case aiPTI_Integer:
            for (unsigned i = 0; i < p.mDataLength / 4; ++i) {
                int v;
                std::memcpy(&v, p.mData + 4 * i, 4);
                std::snprintf(buf, sizeof buf, "%s%d", i ? " " : "", v);
                out += buf;
            }
            return "int " + out;
        case aiPTI_String: {
            std::uint32_t len = 0;
            if (p.mDataLength >= 4) std::memcpy(&len, p.mData, 4);
            if (len > p.mDataLength - 4) len = p.mDataLength - 4;
            return "string \"" + std::string(p.mData + 4, len) + "\"";
        }
        default:
            for (unsigned i = 0; i < p.mDataLength && i < 32; ++i) {
                std::snprintf(buf, sizeof buf, "%02x", static_cast<unsigned char>(p.mData[i]));
                out += buf;
            }
            return "buffer 0x" + out;
    }
}

struct Placed {
    const aiNode* node;
    aiMatrix4x4 world;
};

void walk(const aiNode* n, const aiMatrix4x4& parent, std::vector<Placed>& out) {
    const aiMatrix4x4 w = parent * n->mTransformation;
    out.push_back({n, w});
    for (unsigned i = 0; i < n->mNumChildren; ++i) walk(n->mChildren[i], w, out);
}

aiVector3D unit(aiVector3D v) {
    const float l = v.Length();
    return l > 0 ? v / l : v;
}

void vec(const char* label, const aiVector3D& v) { std::printf(" %s (%.6f, %.6f, %.6f)", label, v.x, v.y, v.z); }

}  // namespace

int main(int argc, char** argv) {
    bool calc = false, findInvalid = true;
    const char* path = nullptr;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--calc-tangents") == 0)
            calc = true;
        else if (std::strcmp(argv[i], "--no-find-invalid-data") == 0)
            findInvalid = false;
        else
            path = argv[i];
    }
    if (!path) {
        std::fprintf(stderr, "usage: %s [--calc-tangents] [--no-find-invalid-data] FILE\n", argv[0]);
        return 2;
    }
    Assimp::Importer importer;
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    unsigned flags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure |
                     aiProcess_FindInvalidData;
    if (calc) flags |= aiProcess_CalcTangentSpace;
    if (!findInvalid) flags &= ~static_cast<unsigned>(aiProcess_FindInvalidData);
    const aiScene* s = importer.ReadFile(path, flags);
    std::printf("file: %s\nassimp: %u.%u.%u   flags: Triangulate|SortByPType|JoinIdenticalVertices|ValidateDataStructure%s%s\n", path,
                aiGetVersionMajor(), aiGetVersionMinor(), aiGetVersionPatch(), findInvalid ? "|FindInvalidData (symphong's)" : " (symphong's without FindInvalidData)",
                calc ? " | CalcTangentSpace" : "");
    if (!s) {
        std::printf("IMPORT FAILED: %s\n", importer.GetErrorString());
        return 1;
    }
    std::vector<Placed> nodes;
    walk(s->mRootNode, aiMatrix4x4(), nodes);

    std::printf("\n== materials (%u)\n", s->mNumMaterials);
    for (unsigned i = 0; i < s->mNumMaterials; ++i) {
        const aiMaterial* m = s->mMaterials[i];
        aiString name;
        m->Get(AI_MATKEY_NAME, name);
        std::printf("  material %u '%s'\n    texture counts:", i, name.C_Str());
        for (unsigned t = aiTextureType_NONE; t <= AI_TEXTURE_TYPE_MAX; ++t)
            std::printf(" %s(%u)=%u", textureTypeName(t), t, m->GetTextureCount(static_cast<aiTextureType>(t)));
        std::printf("\n");
        for (unsigned t = aiTextureType_NONE; t <= AI_TEXTURE_TYPE_MAX; ++t) {
            const auto type = static_cast<aiTextureType>(t);
            for (unsigned k = 0; k < m->GetTextureCount(type); ++k) {
                aiString file;
                aiTextureMapping mapping = aiTextureMapping_UV;
                unsigned uv = 0;
                ai_real blend = -1;
                aiTextureOp op = aiTextureOp_Multiply;
                aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
                const aiReturn r = m->GetTexture(type, k, &file, &mapping, &uv, &blend, &op, modes);
                std::printf("    texture %s(%u)[%u]: '%s' (GetTexture %d) mapping %d uv %u blend %g op %d wrap %d %d%s\n", textureTypeName(t), t, k,
                            file.C_Str(), static_cast<int>(r), static_cast<int>(mapping), uv, blend, static_cast<int>(op), modes[0], modes[1],
                            s->GetEmbeddedTexture(file.C_Str()) ? " (embedded)" : "");
                for (unsigned q = 0; q < m->mNumProperties; ++q) {
                    const aiMaterialProperty& p = *m->mProperties[q];
                    if (p.mSemantic == t && p.mIndex == k) std::printf("      %-28s %s\n", p.mKey.C_Str(), value(p).c_str());
                }
            }
        }
        // Material-wide properties that may carry a bump / normal strength.
        for (unsigned q = 0; q < m->mNumProperties; ++q) {
            const aiMaterialProperty& p = *m->mProperties[q];
            std::string key = p.mKey.C_Str();
            for (auto& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            if (p.mSemantic == 0 && (key.find("bump") != std::string::npos || key.find("normal") != std::string::npos ||
                                     key.find("scale") != std::string::npos || key.find("strength") != std::string::npos))
                std::printf("    material property %-28s %s\n", p.mKey.C_Str(), value(p).c_str());
        }
    }

    std::printf("\n== meshes (%u)\n", s->mNumMeshes);
    for (unsigned i = 0; i < s->mNumMeshes; ++i) {
        const aiMesh* mesh = s->mMeshes[i];
        aiMatrix4x4 world;
        std::string node = "(no node)";
        for (const auto& p : nodes)
            for (unsigned k = 0; k < p.node->mNumMeshes; ++k)
                if (p.node->mMeshes[k] == i) world = p.world, node = p.node->mName.C_Str();
        const aiMatrix3x3 rot(world);
        aiMatrix3x3 normalMatrix = rot;
        normalMatrix.Inverse().Transpose();
        std::printf("  mesh %u '%s' (node '%s'): %u vertices, %u faces, material %u; normals %s, tangents %s, bitangents %s, uv channels", i,
                    mesh->mName.C_Str(), node.c_str(), mesh->mNumVertices, mesh->mNumFaces, mesh->mMaterialIndex, mesh->mNormals ? "yes" : "no",
                    mesh->mTangents ? "yes" : "no", mesh->mBitangents ? "yes" : "no");
        for (unsigned c = 0; c < AI_MAX_NUMBER_OF_TEXTURECOORDS; ++c)
            if (mesh->mTextureCoords[c]) std::printf(" %u(%ud)", c, mesh->mNumUVComponents[c]);
        std::printf("\n");
        for (unsigned v = 0; v < mesh->mNumVertices && v < 8; ++v) {
            std::printf("    v%u:", v);
            vec("p", mesh->mVertices[v]);
            if (mesh->mNormals) vec("N", mesh->mNormals[v]);
            if (mesh->mTangents) vec("T", mesh->mTangents[v]);
            if (mesh->mBitangents) vec("B", mesh->mBitangents[v]);
            if (mesh->mTextureCoords[0]) std::printf(" uv (%.6f, %.6f)", mesh->mTextureCoords[0][v].x, mesh->mTextureCoords[0][v].y);
            if (mesh->mNormals && mesh->mTangents && mesh->mBitangents)
                std::printf(" sign(cross(N,T).B) %+.0f", std::copysign(1.0, (mesh->mNormals[v] ^ mesh->mTangents[v]) * mesh->mBitangents[v]));
            std::printf("\n        world:");
            vec("p", world * mesh->mVertices[v]);
            if (mesh->mNormals) vec("N", unit(normalMatrix * mesh->mNormals[v]));
            if (mesh->mTangents) vec("T", unit(rot * mesh->mTangents[v]));
            if (mesh->mBitangents) vec("B", unit(rot * mesh->mBitangents[v]));
            std::printf("\n");
        }
    }

    std::printf("\n== cameras (%u)\n", s->mNumCameras);
    for (unsigned i = 0; i < s->mNumCameras; ++i) {
        const aiCamera& c = *s->mCameras[i];
        aiMatrix4x4 world;
        for (const auto& p : nodes)
            if (std::strcmp(p.node->mName.C_Str(), c.mName.C_Str()) == 0) world = p.world;
        const aiMatrix3x3 rot(world);
        std::printf("  camera %u '%s': mHorizontalFOV %.9g rad = %.6f deg, mAspect %.9g, near %g, far %g\n", i, c.mName.C_Str(), c.mHorizontalFOV,
                    c.mHorizontalFOV * kDeg, c.mAspect, c.mClipPlaneNear, c.mClipPlaneFar);
        std::printf("    mPosition (%.6f, %.6f, %.6f) mLookAt (%.6f, %.6f, %.6f) mUp (%.6f, %.6f, %.6f)\n", c.mPosition.x, c.mPosition.y,
                    c.mPosition.z, c.mLookAt.x, c.mLookAt.y, c.mLookAt.z, c.mUp.x, c.mUp.y, c.mUp.z);
        const aiVector3D pos = world * c.mPosition, look = unit(rot * c.mLookAt), up = unit(rot * c.mUp);
        std::printf("    in world: position (%.6f, %.6f, %.6f) looks along (%.6f, %.6f, %.6f) up (%.6f, %.6f, %.6f)\n", pos.x, pos.y, pos.z, look.x,
                    look.y, look.z, up.x, up.y, up.z);
        const double a = c.mAspect > 0 ? c.mAspect : 1.0;
        std::printf("    mHorizontalFOV read as the full horizontal angle: vertical %.6f deg; as the half angle: horizontal %.6f deg, vertical %.6f deg\n",
                    2 * std::atan(std::tan(c.mHorizontalFOV / 2) / a) * kDeg, 2 * c.mHorizontalFOV * kDeg,
                    2 * std::atan(std::tan(c.mHorizontalFOV) / a) * kDeg);
    }
    return 0;
}
