/* MasterTool XE arithmetic in C: saturation at the operand type's limits
   (MT-OP-6) with the INTERNAL_OVERFLOW flag (MT-OP-7), binary32 REAL. */
#ifndef STREF_BENCH_SAT_H
#define STREF_BENCH_SAT_H
#include <stdint.h>
#include <stdio.h>

static int internal_overflow;

static inline int16_t sat16(int32_t x) {
  if (x > 32767) { internal_overflow = 1; return 32767; }
  if (x < -32768) { internal_overflow = 1; return -32768; }
  internal_overflow = 0; return (int16_t)x;
}
static inline int32_t sat32(int64_t x) {
  if (x > INT32_MAX) { internal_overflow = 1; return INT32_MAX; }
  if (x < INT32_MIN) { internal_overflow = 1; return INT32_MIN; }
  internal_overflow = 0; return (int32_t)x;
}
static inline int16_t add16(int16_t a, int16_t b) { return sat16((int32_t)a + b); }
static inline int16_t sub16(int16_t a, int16_t b) { return sat16((int32_t)a - b); }
static inline int16_t mul16(int16_t a, int16_t b) { return sat16((int32_t)a * b); }
static inline int32_t add32(int32_t a, int32_t b) { return sat32((int64_t)a + b); }
static inline int32_t sub32(int32_t a, int32_t b) { return sat32((int64_t)a - b); }
static inline int32_t mul32(int32_t a, int32_t b) { return sat32((int64_t)a * b); }

/* REAL + - * : binary32, saturating at +-FLT_MAX with the flag (decision A6). */
#define FLT_MAX_ 3.40282346638528859811704183484516925440e+38f
static inline float satf(float x) {
  if (x > FLT_MAX_) { internal_overflow = 1; return FLT_MAX_; }
  if (x < -FLT_MAX_) { internal_overflow = 1; return -FLT_MAX_; }
  internal_overflow = 0; return x;
}
static inline float addf(float a, float b) { return satf(a + b); }
static inline float subf(float a, float b) { return satf(a - b); }
static inline float mulf(float a, float b) { return satf(a * b); }

/* REAL_TO_INT / REAL_TO_DINT: truncate toward zero, then saturate (C52, C53). */
static inline int16_t real_to_int(float r) {
  if (r != r) return 0;
  if (r >= 32767.0f) return 32767;
  if (r <= -32768.0f) return -32768;
  return (int16_t)r;
}
static inline int32_t real_to_dint(float r) {
  if (r != r) return 0;
  if (r >= 2147483647.0f) return INT32_MAX;
  if (r <= -2147483648.0f) return INT32_MIN;
  return (int32_t)r;
}
#endif
