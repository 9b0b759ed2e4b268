#pragma once
// Output that cannot be written (a full disk, a closed pipe, /dev/full). Unlike unusable
// input, the run itself was fine: the command line prints the message, which names the
// output and says what was kept, and exits with status 1.
#include <stdexcept>
#include <string>

namespace rtu {

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rtu
