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

}  // namespace brdf
