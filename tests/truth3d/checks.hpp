// The truth3d tests' check: one line "ok  what" or "FAIL what" per check, failures counted
// for the exit code (main returns 1 when g_fail > 0).
#pragma once

#include <cstdio>
#include <string>

namespace ggins_test {

inline int g_fail = 0;

inline void check(bool ok, const std::string& what) {
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  if (!ok) ++g_fail;
}

}  // namespace ggins_test
