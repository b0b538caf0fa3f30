// Atomic outputs (DESIGN §3): write to a temporary file beside the target, flush it to disk,
// then rename over the target, so a failure or a kill never leaves a half-written file.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace brdf {

// Calls `write` with a stream on a temporary file in the target's directory, then renames it
// to `path`. If `write` throws or the stream fails, the temporary is removed, `path` is left
// as it was, and the error propagates (stream failures as OutputError naming `path`).
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                         bool binary = false);

// The same protocol for writers that insist on opening a file by name (e.g. OpenEXR): calls
// `write_to` with the path of a temporary file beside `path`, then flushes and renames it.
// Errors from `write_to` propagate after the temporary is removed.
void WriteFileAtomicallyByName(const std::string& path,
                               const std::function<void(const std::string& temporary)>& write_to);

}  // namespace brdf
