// render/checkpoint.h — a render's state on disk, so that a render killed, preempted or stopped can be
// resumed to the image an uninterrupted render gives, bit for bit. The file holds what identifies the
// render (the scene's fingerprint and every setting that changes pixel values, as JSON) and its state
// (render/render_state.h: per-pixel sums, per-tile sample counts, statistics), followed by a checksum of
// everything before it. It is written durably (temporary file, fsync, rename, fsync of the directory,
// io/files.h), so a kill at any moment leaves the previous checkpoint or the new one, never half of one;
// a file that is damaged anyway (checksum, size) is refused, never read in part.
//
// Layout: the line "symphong checkpoint 1\n"; one line of JSON (the header); then, little-endian, the
// tile counts (uint32 each), the sums, sums of squares (3 doubles a pixel each) and sums of squared
// luminance (1 double a pixel); then a 64-bit checksum (util hashing of the bytes above).
#pragma once

#include "render/render_state.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <istream>
#include <string>

namespace symphong {

/// What identifies a render: a checkpoint resumes only the render it was made by.
struct RenderIdentity {
    std::string scene;        ///< the scene as named on the command line (for messages)
    std::string sceneHash;    ///< sceneFingerprint() of the loaded scene, hex
    nlohmann::json settings;  ///< every setting that changes pixel values (render/settings.h)
};

/// A fingerprint of a loaded scene: the bytes of its file (when `spec` names one) and the description
/// of what was loaded from it (render/describe.h: geometry counts, bounds, camera, materials, lights,
/// environment, textures), as 16 hex digits. An edit of the scene file or of its materials changes it.
std::string sceneFingerprint(const Scene& scene, const std::string& spec);

/// Writes the checkpoint durably. Throws InputError naming `path` when it cannot.
void writeCheckpoint(const std::string& path, const RenderIdentity& identity, const RenderState& state);

/// Reads a checkpoint into `identity` and `state`. Throws InputError naming `path` when it is not a
/// checkpoint, is damaged or truncated, or holds more than io/memory.h allows.
void readCheckpoint(const std::string& path, RenderIdentity& identity, RenderState& state);

/// readCheckpoint from a stream already open on the checkpoint (`path` names it in messages). Every byte
/// and the size come from the file the stream opened, so a checkpoint renamed over `path` while it is read
/// (a rank of a killed job still writing it) is not mixed with it.
void readCheckpoint(std::istream& in, const std::string& path, RenderIdentity& identity, RenderState& state);

/// Throws InputError naming `path` when the checkpoint's render differs from `now`: another scene, or
/// the first setting that differs ("spp 1024 in the checkpoint, 4096 now").
void requireSameRender(const std::string& path, const RenderIdentity& saved, const RenderIdentity& now);

/// When to write: every `interval` seconds of render time, early enough that the next pass would not
/// carry the work since the last checkpoint past the interval, and at the end.
class CheckpointSchedule {
public:
    explicit CheckpointSchedule(double interval, double now) : interval_(interval), last_(now) {}
    /// True when a checkpoint is due after a pass that ended at render time `now`, the next expected to
    /// take `nextPass` seconds (`last`: the render stops after this pass).
    bool due(double now, double nextPass, bool last) const { return last || now + nextPass - last_ > interval_; }
    void written(double now) { last_ = now; }

private:
    double interval_, last_;
};

}  // namespace symphong
