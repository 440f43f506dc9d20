/* CMocka includes for tests that must not touch long double libm/printf
 * (the -mlong-double-64 build). */
#ifndef GGINS_TESTS_COMMON_Q_H
#define GGINS_TESTS_COMMON_Q_H
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#endif
