#include "core/errors.hpp"

namespace bakesim {

InputError::InputError(std::string where, const std::string& what)
    : Error(where.empty() ? what : where + ": " + what), where_(std::move(where)), detail_(what) {}

}  // namespace bakesim
