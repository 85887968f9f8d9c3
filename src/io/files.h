// io/files.h — reading text files and writing any file atomically (a temporary file beside the target,
// renamed into place), so the target is either complete or untouched.
#pragma once

#include <functional>
#include <string>

namespace symphong {

/// The extension of a path, lower-cased, with its dot (".obj"), or "" when it has none.
std::string lowerExtension(const std::string& path);

/// Reads a whole file; throws InputError naming the path when it is missing or unreadable.
std::string readTextFile(const std::string& path);

/// The temporary path writeAtomically uses for `path`: a hidden file in the same directory.
std::string temporaryPathFor(const std::string& path);

/// Creates the directory of `path` if needed and checks that a file can be created there (without
/// leaving one), so that a long run fails before it starts, not after. Throws InputError naming `path`.
void checkCanCreate(const std::string& path);

/// Runs write(tmp) for a temporary path in the target's directory, then renames it onto `path`; on any
/// failure removes the temporary file and throws InputError naming `path`.
void writeAtomically(const std::string& path, const std::function<void(const std::string& tmp)>& write);

/// writeAtomically that also survives a crash of the machine: the temporary file is flushed to the disk
/// (fsync) before it is renamed, and the directory after, so the target is the old file or the whole new
/// one even after a power cut (checkpoints, render/checkpoint.h).
void writeDurably(const std::string& path, const std::function<void(const std::string& tmp)>& write);

/// writeAtomically for the bytes of a string (text or binary).
void writeFile(const std::string& path, const std::string& bytes);

}  // namespace symphong
