#pragma once
/// @file expect_error.hpp  Asserting that a call throws hemicontact::Error with exit code 2 (bad input)
/// and a message naming what is wrong.

#include <hemicontact/core/error.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

/// Expect the string @p text to contain @p part (the text is printed when it does not).
#define EXPECT_CONTAINS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << "text: " << (text)

namespace hemicontact::test {

/// Expect @p fn to throw an input Error whose message contains every string of @p parts.
inline void expect_input_error(const std::function<void()>& fn, const std::vector<std::string>& parts) {
  try {
    fn();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT);
    const std::string msg = e.what();
    for (const auto& part : parts)
      EXPECT_NE(msg.find(part), std::string::npos) << "message: " << msg << "\nmissing: " << part;
    return;
  }
  ADD_FAILURE() << "no hemicontact::Error thrown";
}

}  // namespace hemicontact::test
