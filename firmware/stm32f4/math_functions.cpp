// fmaxf as C99 defines it (a NaN argument yields the other one), in a few instructions: newlib's
// goes through __fpclassifyf, 116 B for what the control loop and the console's `drive` use to
// take the larger of two speeds. Built outside LTO like string_functions.cpp.

extern "C" float fmaxf(float a, float b) {
  // a NaN `a` fails the comparison and yields b; a NaN `b` yields a.
  return a >= b || b != b ? a : b;
}
