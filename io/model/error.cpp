// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/error.h"

#include <exception>
#include <filesystem>
#include <new>

namespace dtf {

namespace {

// "Too many levels of symbolic links" -> "too many levels ...": the system's messages inside a sentence.
std::string lowerFirst(std::string s) {
  if (!s.empty() && s[0] >= 'A' && s[0] <= 'Z') s[0] = static_cast<char>(s[0] - 'A' + 'a');
  return s;
}

} // namespace

std::string notARegularFile(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::is_regular_file(st)) return "";
  if (fs::is_directory(st)) return "it is a folder";
  if (fs::exists(st)) return "it is not a regular file (a device, pipe or socket)";
  if (ec && ec != std::errc::no_such_file_or_directory && ec != std::errc::not_a_directory)
    return "it cannot be examined: " + lowerFirst(ec.message()); // a loop of links, a folder without access
  return "no such file";
}

std::string filesystemErrorMessage(const std::exception& error) {
  const auto* fe = dynamic_cast<const std::filesystem::filesystem_error*>(&error);
  if (!fe) return "";
  const std::filesystem::filesystem_error& e = *fe;
  std::string where = e.path1().string();
  if (!e.path2().empty()) where += " -> " + e.path2().string();
  const std::string why = lowerFirst(e.code().message());
  return where.empty() ? why : where + ": " + why;
}

void rethrowWithContext(const std::string& context) {
  try {
    throw;
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  } catch (const UsageError& e) {
    throw UsageError(context + ": " + e.what());
  } catch (const GlError& e) {
    throw GlError(context + ": " + e.what());
  } catch (const Error& e) {
    throw Error(context + ": " + e.what());
  } catch (const std::bad_alloc&) {
    throw InputError(context + ": out of memory");
  } catch (const std::filesystem::filesystem_error& e) {
    throw InputError(context + ": " + filesystemErrorMessage(e));
  } catch (const std::exception& e) {
    throw Error(context + ": " + e.what());
  }
}

std::string currentExceptionMessage() {
  try {
    throw;
  } catch (const std::bad_alloc&) {
    return "out of memory";
  } catch (const std::filesystem::filesystem_error& e) {
    return filesystemErrorMessage(e);
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "unknown error";
  }
}

} // namespace dtf
