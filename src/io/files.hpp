#pragma once
// Atomic file output: write to a temporary name in the same directory, then
// rename, so readers never see a half-written file.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace bakesim {

// Throws IoError naming the path when the directory is unwritable or full.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);
// Removes the temporaries write_file_atomic leaves when its process is killed
// mid-write (".NAME.tmpPID") in `dir` itself (not below it); returns how many.
int remove_atomic_temporaries(const std::filesystem::path& dir);
// Whether a file name is such a temporary.
bool is_atomic_temporary(const std::string& name);
// Appends `bytes` and flushes them to the disk (a crash loses at most the
// line being written); throws IoError naming the path on failure.
void append_file(const std::filesystem::path& path, std::string_view bytes);
// The whole file; throws InputError naming the path when it cannot be read,
// is not a regular file (a FIFO or a device would hang or never end) or is
// longer than `max_bytes`.
std::string read_file(const std::filesystem::path& path, std::uintmax_t max_bytes = UINTMAX_MAX);
// Creates a directory (and parents); throws IoError on failure.
void ensure_directory(const std::filesystem::path& dir);

// Frame files are named by their frame number, zero-padded to five digits
// ("00042"; frame 123456 is "123456"). Listings sort them by number, never
// by name, so frames past 99,999 stay in order.
std::string frame_stem(int frame);
// The frame number a file stem names: digits only, at most nine; nullopt otherwise.
std::optional<int> frame_number(const std::string& stem);

}  // namespace bakesim
