#pragma once
// Typed exceptions. The library throws, never exits; front ends map these to
// messages and exit codes (InputError -> 2, SimulationError -> 3, others -> 1).
#include <stdexcept>
#include <string>

namespace bakesim {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bad user input: a scene, a mesh file, a command-line value. `where` names the
// file and, when known, the key path inside it ("scene.json: bodies[2].radius").
class InputError : public Error {
 public:
  InputError(std::string where, const std::string& what);
  const std::string& where() const { return where_; }
  const std::string& detail() const { return detail_; }

 private:
  std::string where_;
  std::string detail_;
};

// The simulation reached an invalid state (NaN, inverted element, ...).
class SimulationError : public Error {
 public:
  using Error::Error;
};

// Files could not be written or read for reasons other than their content.
class IoError : public Error {
 public:
  using Error::Error;
};

}  // namespace bakesim
