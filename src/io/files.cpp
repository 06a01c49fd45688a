#include "io/files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/errors.hpp"

namespace bakesim {

namespace fs = std::filesystem;

std::string read_file(const fs::path& p, std::uintmax_t max_bytes) {
  std::error_code ec;
  const auto status = fs::status(p, ec);
  if (!fs::exists(status)) throw InputError(p.string(), "not found");
  if (!fs::is_regular_file(status))
    throw InputError(p.string(), fs::is_directory(status) ? "is a directory, not a file"
                                                          : "is not a regular file (a FIFO, socket or device)");
  const std::uintmax_t size = fs::file_size(p, ec);
  if (!ec && size > max_bytes)
    throw InputError(p.string(), "is " + std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
                                     " this file may have");
  std::ifstream in(p, std::ios::binary);
  if (!in) throw InputError(p.string(), "cannot be read");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void append_file(const fs::path& path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(path.string() + ": cannot write: " + std::strerror(errno));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t w = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0) {
      const int err = errno;
      ::close(fd);
      throw IoError(path.string() + ": write failed: " + std::strerror(err));
    }
    done += static_cast<std::size_t>(w);
  }
  if (::fdatasync(fd) != 0 && errno != EINVAL) {
    const int err = errno;
    ::close(fd);
    throw IoError(path.string() + ": write failed: " + std::strerror(err));
  }
  if (::close(fd) != 0) throw IoError(path.string() + ": write failed: " + std::strerror(errno));
}

void ensure_directory(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(dir.string() + ": cannot create directory: " + ec.message());
  if (!fs::is_directory(dir, ec)) throw IoError(dir.string() + ": exists and is not a directory");
}

namespace {
const std::string kTemporaryMark = ".tmp";

fs::path temporary_for(const fs::path& path) {
  return path.parent_path() / ("." + path.filename().string() + kTemporaryMark + std::to_string(::getpid()));
}

}  // namespace

bool is_atomic_temporary(const std::string& name) {
  const std::size_t mark = name.rfind(kTemporaryMark);
  if (name.empty() || name[0] != '.' || mark == std::string::npos || mark + kTemporaryMark.size() == name.size())
    return false;
  for (std::size_t i = mark + kTemporaryMark.size(); i < name.size(); ++i)
    if (name[i] < '0' || name[i] > '9') return false;
  return true;
}

int remove_atomic_temporaries(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> found;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec))
    if (it->is_regular_file(ec) && is_atomic_temporary(it->path().filename().string())) found.push_back(it->path());
  int removed = 0;
  for (const auto& p : found) removed += fs::remove(p, ec) ? 1 : 0;
  return removed;
}

void write_file_atomic(const fs::path& path, std::string_view bytes) {
  const fs::path tmp = temporary_for(path);
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(path.string() + ": cannot write: " + std::strerror(errno));
  // Any failure closes and removes the temporary, then names the file and the cause.
  auto fail = [&](const char* what) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    throw IoError(path.string() + ": " + what + ": " + std::strerror(err));
  };
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t w = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (w < 0) {
      if (errno == EINTR) continue;
      fail("write failed");
    }
    done += static_cast<std::size_t>(w);
  }
  // Flushed to the disk before the rename, so a crash or power loss leaves the
  // old file or the new one, and a full disk shows up here at the latest.
  if (::fsync(fd) != 0 && errno != EINVAL) fail("write failed");
  const int closed = ::close(fd);
  fd = -1;
  if (closed != 0) fail("write failed");
  if (::rename(tmp.c_str(), path.c_str()) != 0) fail("cannot rename into place");
}

std::string frame_stem(int frame) {
  std::string s = std::to_string(frame);
  return s.size() < 5 ? std::string(5 - s.size(), '0') + s : s;
}

std::optional<int> frame_number(const std::string& stem) {
  if (stem.empty() || stem.size() > 9) return std::nullopt;
  int n = 0;
  for (const char c : stem) {
    if (c < '0' || c > '9') return std::nullopt;
    n = n * 10 + (c - '0');
  }
  return n;
}

}  // namespace bakesim
