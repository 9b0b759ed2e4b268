// Threads carry names that say which stage they run, as ps, top and perf show them: the name
// given is the one the kernel keeps (cut to its 15 characters), and a replay's reading and
// framing threads are named for their stage.
#include "core/thread_name.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <string>
#include <thread>

#include "capture/read_ahead.hpp"
#include "item_transcript.hpp"

namespace rtu {
namespace {

// What the kernel shows for the calling thread (ps -L, top -H).
std::string kernel_name_of_this_thread() {
  std::ifstream comm("/proc/thread-self/comm");
  std::string name;
  std::getline(comm, name);
  return name;
}

TEST(ThreadName, AThreadIsShownByTheNameItGaveItself) {
  std::string named;
  std::string shown;
  std::thread t([&] {
    name_this_thread("rtu-test");
    named = this_thread_name();
    shown = kernel_name_of_this_thread();
  });
  t.join();
  EXPECT_EQ(named, "rtu-test");
  EXPECT_EQ(shown, "rtu-test");
  EXPECT_NE(this_thread_name(), "rtu-test");  // the naming thread alone
}

TEST(ThreadName, ALongNameKeepsItsFirstFifteenCharacters) {
  std::string shown;
  std::thread t([&] {
    name_this_thread("rtu-a-name-longer-than-the-kernel-keeps");
    shown = kernel_name_of_this_thread();
  });
  t.join();
  EXPECT_EQ(shown, "rtu-a-name-long");
}

// A reader that notes the name of the thread it is read on, and ends at once.
class NameNotingReader final : public CaptureReader {
 public:
  explicit NameNotingReader(std::string& name) : name_(name) {}
  bool read(CaptureConsumer& /*to*/) override {
    name_ = this_thread_name();
    return false;
  }
  [[nodiscard]] std::string name() const override { return "name-noting"; }

 private:
  std::string& name_;
};

TEST(ThreadName, AReadAheadReadsOnAThreadNamedForReading) {
  std::string name;
  {
    ReadAhead ahead(std::make_unique<NameNotingReader>(name));
    testing::ItemTranscript t;
    while (ahead.read(t)) {
    }
  }
  EXPECT_EQ(name, "rtu-read");
}

}  // namespace
}  // namespace rtu
