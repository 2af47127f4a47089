#pragma once
// File helpers: whole-file reads, content hashes, atomic writes.
#include <string>

namespace armstudy {

// Reads a whole file; throws InputError(path) when it cannot be opened.
std::string readFileOrThrow(const std::string& path);

// Content fingerprint of bytes: 64-bit FNV-1a as 16 hex digits, prefixed "fnv1a64:". Used to
// record which inputs a run read and to detect changed inputs; not a cryptographic hash.
std::string contentHash(const std::string& bytes);
std::string fileHash(const std::string& path);

// Writes `content` to `path` atomically: a temporary file beside it, flushed, then renamed over
// the target. An interrupted run never leaves a half-written file. Creates parent folders.
void writeFileAtomic(const std::string& path, const std::string& content);

}  // namespace armstudy
