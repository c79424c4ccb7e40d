// SPDX-License-Identifier: GPL-3.0-or-later
// Error types shared by every module. User, data and environment problems throw a type derived from
// dtf::Error; callers add context on the way up ("while reading tensor volume X: ...") and the app prints
// the whole chain (CLI) or shows it in a modal (GUI).
#pragma once

#include <exception>
#include <stdexcept>
#include <string>

namespace dtf {

// Base of all product errors. what() holds the full message chain, outermost context first.
class Error : public std::runtime_error {
public:
  explicit Error(const std::string& msg) : std::runtime_error(msg) {}
};

// Bad input data or files (CLI exit code 2).
class InputError : public Error {
public:
  using Error::Error;
};

// Bad command-line usage (CLI exit code 1).
class UsageError : public Error {
public:
  using Error::Error;
};

// GL context, shader or GPU-memory failure (CLI exit code 3).
class GlError : public Error {
public:
  using Error::Error;
};

// Rethrows the active exception with `context` prepended, keeping its type. Call inside a catch block.
[[noreturn]] void rethrowWithContext(const std::string& context);

// Why `path` cannot be read as a file: "no such file", "it is a folder" or "it is not a regular file (a
// device, pipe or socket)"; empty when it is a regular file (or a link to one).
std::string notARegularFile(const std::string& path);

// A file system call's failure (std::filesystem::filesystem_error) as the product words it: "PATH: too many
// levels of symbolic links"; empty for any other exception. Such a failure is an input problem (CLI exit
// code 2, dtfabric.FileError in Python): rethrowWithContext turns it into an InputError,
// currentExceptionMessage into this message.
std::string filesystemErrorMessage(const std::exception& e);

// The message of the exception being handled ("out of memory" for std::bad_alloc, "unknown error" for what
// is not a std::exception). Call inside a catch block.
std::string currentExceptionMessage();

} // namespace dtf
