// io/ — everything that crosses the program's boundary with the file system: the error type for bad
// input, reading text files, and writing images (PNG, OpenEXR) atomically so that a failed run never
// leaves a half-written file behind.
#pragma once

#include <stdexcept>
#include <string>

namespace symphong {

/// Bad input from the user: a missing or malformed file, an invalid value. The message is one line that
/// names the file, the line (where known) and the offending value. The command line turns it into exit
/// code 2.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Bad input of one kind: a file that the user named does not exist. An InputError like the others
/// (exit code 2); callers that tell the two apart (the Python module raises FileNotFoundError for it,
/// ValueError for the others) catch it first.
class MissingFileError : public InputError {
public:
    using InputError::InputError;
};

}  // namespace symphong
