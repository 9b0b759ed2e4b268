#pragma once
// An output file that appears only when the command succeeds: it is written under a
// temporary name next to it (PATH.partial) and renamed over PATH by commit(). A run that fails
// (damaged input, a full disk) removes the temporary file, so it never leaves a partial
// output and never spoils an older file of the same name. A path that is already something
// other than a file (/dev/null, a FIFO a reader waits on, a terminal) is written directly:
// renaming a file over it would replace the device or pipe with a plain file.
#include <string>

namespace rtu::app {

class FileReplacedOnSuccess {
 public:
  explicit FileReplacedOnSuccess(std::string path);
  ~FileReplacedOnSuccess();
  FileReplacedOnSuccess(const FileReplacedOnSuccess&) = delete;
  FileReplacedOnSuccess& operator=(const FileReplacedOnSuccess&) = delete;

  // Where to write.
  [[nodiscard]] const std::string& temporary_path() const { return temporary_; }
  // Renames the written file to its path; throws OutputError when it cannot.
  void commit();

 private:
  std::string path_;
  std::string temporary_;
  bool direct_ = false;  // path_ is not a regular file: written as it is
  bool committed_ = false;
};

}  // namespace rtu::app
