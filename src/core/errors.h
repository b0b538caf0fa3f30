// Typed errors. Library code throws; only main() turns them into exit codes (DESIGN §3), through
// ExitStatus below: UsageError, InputError and OutputError -> 2, ComputeError -> 3.
#pragma once

#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>

namespace brdf {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  // The process's exit status for this error (DESIGN §3).
  virtual int exit_status() const { return 2; }
};

// A bad command line or model string: exit status 2.
class UsageError : public Error {
 public:
  using Error::Error;
};

// A file that cannot be read or is not what it claims to be: exit status 2. The message
// always names the file and, where it applies, the line or byte offset.
class InputError : public Error {
 public:
  InputError(const std::string& path, const std::string& what)
      : Error(path + ": " + what), path_(path) {}
  // The file (or argument) named at the start of the message, for callers that report it on
  // its own (the Python module's InputError.path).
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// A text file broken at a given line (1-based).
class ParseError : public InputError {
 public:
  ParseError(const std::string& path, int64_t line, const std::string& what)
      : InputError(path, "line " + std::to_string(line) + ": " + what), line_(line) {}
  int64_t line() const { return line_; }

 private:
  int64_t line_;
};

// A binary file broken at a given byte offset (0-based).
class ByteError : public InputError {
 public:
  ByteError(const std::string& path, int64_t offset, const std::string& what)
      : InputError(path, "byte " + std::to_string(offset) + ": " + what), offset_(offset) {}
  int64_t offset() const { return offset_; }

 private:
  int64_t offset_;
};

// An output that cannot be written: exit status 2 (the user named a bad path).
class OutputError : public Error {
 public:
  OutputError(const std::string& path, const std::string& what)
      : Error(path + ": " + what), path_(path) {}
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// A computation that failed (e.g. a fit that did not converge): exit status 3.
class ComputeError : public Error {
 public:
  using Error::Error;
  int exit_status() const override { return 3; }
};

// The one map from an error to the process's exit status (DESIGN §3) and the message the user
// reads: an Error's own status; 1 for anything else, an internal error (out of memory included).
int ExitStatus(const std::exception_ptr& error, std::string* message);

}  // namespace brdf
