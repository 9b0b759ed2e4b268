#include "core/thread_name.hpp"

#include <pthread.h>

#include <algorithm>
#include <array>

namespace rtu {
namespace {

constexpr std::size_t kMaxNameLength = 15;  // the kernel's task name, without its terminator

}  // namespace

void name_this_thread(std::string_view name) {
  std::array<char, kMaxNameLength + 1> text{};
  const std::size_t length = std::min(name.size(), kMaxNameLength);
  std::copy_n(name.begin(), length, text.begin());
  pthread_setname_np(pthread_self(), text.data());
}

std::string this_thread_name() {
  std::array<char, kMaxNameLength + 1> text{};
  if (pthread_getname_np(pthread_self(), text.data(), text.size()) != 0) return {};
  return text.data();
}

}  // namespace rtu
