/// \file output_directory.hpp
/// One run per output directory: a run holds an exclusive lock on
/// `DIR/.tensormass.lock` (flock) for as long as it writes into DIR, and a
/// second run into DIR is refused naming the holder's process id. Taking
/// the lock also removes the temporaries (`*.tmp-PID`, atomic_file.hpp)
/// that runs killed while writing left behind.
#ifndef TENSORMASS_IO_OUTPUT_DIRECTORY_HPP
#define TENSORMASS_IO_OUTPUT_DIRECTORY_HPP

#include <string>

namespace tensormass::io {

/// The name of the lock file inside an output directory.
inline constexpr const char* kOutputLockFile = ".tensormass.lock";

class OutputDirectoryLock {
 public:
  /// Creates `directory` when missing and locks it; InputError naming the
  /// directory when it cannot be created or written, or when another run
  /// (this process included) holds it.
  explicit OutputDirectoryLock(const std::string& directory);
  ~OutputDirectoryLock();
  OutputDirectoryLock(const OutputDirectoryLock&) = delete;
  OutputDirectoryLock& operator=(const OutputDirectoryLock&) = delete;

  /// The temporaries of dead runs removed when the lock was taken.
  int removed_temporaries() const { return removed_; }
  /// Lets another run take the directory (also done by the destructor).
  void release();

 private:
  std::string directory_;
  int fd_ = -1;
  int removed_ = 0;
};

}  // namespace tensormass::io

#endif
