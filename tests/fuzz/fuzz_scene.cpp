// Fuzz target: the scene loader (JSON syntax, schema, cross-checks, setup
// building) must turn any input into a Scene or an InputError, nothing else.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/errors.hpp"
#include "io/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    bakesim::Scene scene = bakesim::parse_scene(text, "fuzz.json", ".");
    (void)scene;
  } catch (const bakesim::InputError&) {
  }
  return 0;
}
