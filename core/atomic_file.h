// writeAtomically: a file appears whole or not at all. `write` writes it under a temporary name beside
// `path` (the same folder, so the rename is atomic there; the name ends with path's own file name, so
// writers that go by the extension, .nii.gz included, still choose the format); once `write` returns,
// the temporary is renamed over `path`. When `write` throws, the temporary is removed and `path`, if
// it was there, stays as it was. A process killed mid-write leaves at most a temporary
// (".<pid>-<n>@<host>.partial.<name>"), never a torn `path`; the next successful write of `path`
// removes such temporaries of this host whose process is gone (another host's, on a shared
// filesystem, may be live: they stay).
#pragma once
#include <functional>
#include <string>

namespace isoatlas {

void writeAtomically(const std::string& path, const std::function<void(const std::string& temporary)>& write);

// Throws Error (bad input) naming `path` unless its folder exists: commands check their outputs with it
// before any work, and writeAtomically before it writes.
void requireOutputFolder(const std::string& path);

// `bytes` as the whole of `path` (text or binary), through writeAtomically.
void writeFileAtomically(const std::string& path, const std::string& bytes);

// The temporary name writeAtomically writes `path` under first.
std::string temporaryPathFor(const std::string& path);

// Renames a finished temporary over `path` (throws Error naming path when it cannot).
void replaceWith(const std::string& temporary, const std::string& path);

}  // namespace isoatlas
