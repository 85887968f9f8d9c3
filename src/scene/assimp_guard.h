// scene/assimp_guard.h — Assimp's importers tried first in a child process (scene/assimp_guard.cpp), so
// that a file on which Assimp 5.2 itself crashes or exhausts memory is an InputError, not a crash.
#pragma once

#include <cstdint>
#include <string>

struct aiScene;
namespace Assimp {
class Importer;
}

namespace symphong {

/// Reads `path` with `importer` as every load does (triangulated, sorted by primitive type, identical
/// vertices joined, validated; points and lines are kept so that the load can say they are not drawn;
/// no FindInvalidData, which deletes a flat mesh's tangents because they are all alike); null when
/// Assimp refuses it or gives an incomplete scene (its message: importer.GetErrorString()).
const aiScene* importWithAssimp(Assimp::Importer& importer, const std::string& path);

/// Reads `path` with importWithAssimp in a child process under
/// a limit on its address space. Throws InputError naming the file when the child crashed (the signal's
/// name) or ran out of memory; returns otherwise, whether Assimp read the file or refused it with a
/// message (the caller's own read reports that). SYMPHONG_ASSIMP_IN_PROCESS=1 skips it.
void checkAssimpInChild(const std::string& path);

/// The child's address-space limit for a file of this many bytes: 200 times its size, at least 2 GiB,
/// at most the machine's memory budget (io/memory.h).
std::uint64_t assimpChildMemoryLimit(std::uint64_t fileBytes);

}  // namespace symphong
