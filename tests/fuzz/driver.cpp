// A libFuzzer-compatible driver for builds without libFuzzer (the normal gcc
// build and ctest): runs every seed file, then a fixed number of
// deterministic mutations of the seeds (byte flips, insertions, deletions,
// truncations, splices). An exception other than InputError, or a crash,
// fails the run. Usage: DRIVER ITERATIONS SEED_FILE_OR_DIR...
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::uint64_t next(std::uint64_t& s) {
  s ^= s << 13, s ^= s >> 7, s ^= s << 17;
  return s;
}

std::string mutate(const std::vector<std::string>& seeds, std::uint64_t& s) {
  std::string m = seeds[next(s) % seeds.size()];
  const int edits = 1 + int(next(s) % 8);
  for (int e = 0; e < edits; ++e) {
    const std::size_t at = m.empty() ? 0 : next(s) % (m.size() + 1);
    switch (next(s) % 6) {
      case 0:
        if (at < m.size()) m[at] = char(next(s));
        break;                                                                        // flip a byte
      case 1: m.insert(at, 1, "{}[]\",:0123456789-.eE \n\t\\"[next(s) % 25]); break;  // a syntax character
      case 2:
        if (at < m.size()) m.erase(at, 1 + next(s) % 16);
        break;                      // delete a run
      case 3: m.resize(at); break;  // truncate
      case 4: {
        const std::string& o = seeds[next(s) % seeds.size()];  // splice another seed
        if (!o.empty()) {
          const std::size_t from = next(s) % o.size();
          m.insert(at, o.substr(from, 1 + next(s) % 64));
        }
        break;
      }
      default: m.insert(at, std::to_string(std::int64_t(next(s)))); break;  // a big number
    }
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s ITERATIONS SEED_FILE_OR_DIR...\n", argv[0]);
    return 2;
  }
  const long iterations = std::atol(argv[1]);
  std::vector<std::string> seeds;
  for (int a = 2; a < argc; ++a) {
    std::vector<std::filesystem::path> files;
    if (std::filesystem::is_directory(argv[a])) {
      for (const auto& e : std::filesystem::recursive_directory_iterator(argv[a]))
        if (e.is_regular_file()) files.push_back(e.path());
    } else {
      files.emplace_back(argv[a]);
    }
    for (const auto& f : files) {
      std::ifstream in(f, std::ios::binary);
      std::ostringstream ss;
      ss << in.rdbuf();
      seeds.push_back(ss.str());
    }
  }
  if (seeds.empty()) seeds.emplace_back();
  try {
    for (const auto& s : seeds) LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
    std::uint64_t state = 0x9E3779B97F4A7C15ull;
    for (long i = 0; i < iterations; ++i) {
      const std::string m = mutate(seeds, state);
      LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(m.data()), m.size());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz driver: an input escaped with %s\n", e.what());
    return 1;
  }
  std::printf("fuzz driver: %zu seeds and %ld mutations ran clean\n", seeds.size(), iterations);
  return 0;
}
