#pragma once
// Unusable input or configuration. The message always says where (file and line, or byte
// offset) and what was expected; the command line prints it and exits with status 2.
#include <stdexcept>
#include <string>

namespace rtu {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rtu
