// A figure a physics test measures: recorded as a test property (in ctest's XML) and printed
// as "measured KEY: VALUE", the line the docs and the notes quote.
#pragma once
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

inline void report(const std::string& key, const std::string& value) {
  ::testing::Test::RecordProperty(key, value);
  std::printf("measured %s: %s\n", key.c_str(), value.c_str());
}
