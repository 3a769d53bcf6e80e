#include <hemicontact/core/options.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/text.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>

namespace hemicontact {

long parse_integer_option(const std::string& key, const std::string& value, long lo, long hi) {
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(value.c_str(), &end, 10);
  // The whole text a number (no "8abc", no embedded NUL), within long and the range.
  if (value.empty() || *end != '\0' || end != value.c_str() + value.size() || errno == ERANGE || x < lo || x > hi)
    throw Error(key + ": expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got '" +
                    printable(value) + "'",
                EXIT_USAGE);
  return x;
}

double parse_positive_option(const std::string& key, const std::string& value) {
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || end != value.c_str() + value.size() || !(x > 0) || !std::isfinite(x))
    throw Error(key + ": expected a positive number, got '" + printable(value) + "'", EXIT_USAGE);
  return x;
}

std::string shell_quote(const std::string& text) {
  const bool plain = !text.empty() && text.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                             "0123456789_-+=.,/:@%") == std::string::npos;
  if (plain) return text;
  std::string q = "'";
  for (char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string shell_command(const std::vector<std::string>& argv) {
  std::string c;
  for (const std::string& a : argv) c += (c.empty() ? "" : " ") + shell_quote(a);
  return c;
}

int run_program(const std::string& program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const Error& e) {
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(), e.what());
    return e.code();
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(),
                 out_of_memory_message("'" + program + "' (an allocation failed: std::bad_alloc)").c_str());
    return EXIT_INPUT;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", program.c_str(), e.what());
    return EXIT_INTERNAL;
  }
}

}  // namespace hemicontact
