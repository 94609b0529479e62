/* EXPECT_ERROR(call, code, fragment): the call returns `code` and rl_last_error() contains
 * `fragment`; one line per check.  For the integrator tests of bad input (test_api, test_stepops). */
#ifndef ROTLEAP_TEST_EXPECT_ERROR_H
#define ROTLEAP_TEST_EXPECT_ERROR_H
#include "../testutil.h"

#define EXPECT_ERROR(call, code, fragment)                                                       \
  do {                                                                                           \
    int st_ = (call);                                                                            \
    const char *m_ = rl_last_error();                                                            \
    int ok_ = st_ == (code) && strstr(m_, fragment) != NULL;                                     \
    printf("check %-40s -> %s: \"%s\" %s\n", #code, rl_strerror(st_), m_, ok_ ? "ok" : "FAIL"); \
    assert_true(ok_);                                                                            \
  } while (0)

#endif
