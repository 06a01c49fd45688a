#pragma once
// Atomic file output: write to a temporary name in the same directory, then
// rename, so readers never see a half-written file.
#include <filesystem>
#include <string>
#include <string_view>

namespace bakesim {

// Throws IoError naming the path when the directory is unwritable or full.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);
// Removes the temporaries write_file_atomic leaves when its process is killed
// mid-write (".NAME.tmpPID"), anywhere below `dir`; returns how many.
int remove_atomic_temporaries(const std::filesystem::path& dir);
// The whole file; throws InputError naming the path when it cannot be read.
std::string read_file(const std::filesystem::path& path);
// Creates a directory (and parents); throws IoError on failure.
void ensure_directory(const std::filesystem::path& dir);

}  // namespace bakesim
