// The simulation library's tests print one line a check ("ok" or "FAIL" and what was
// measured) and count the failures in g_fail; main returns g_fail ? 1 : 0.
#pragma once

#include <cstdio>

static int g_fail = 0;
#define CHECK(c, ...)                          \
  do {                                         \
    std::printf("%s ", (c) ? "ok  " : "FAIL"); \
    std::printf(__VA_ARGS__);                  \
    std::printf("\n");                         \
    if (!(c)) ++g_fail;                        \
  } while (0)
