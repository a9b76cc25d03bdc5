/* The same computation as lreal.st under the nexto preset, CALLS scan cycles
   of 1000 iterations: binary64 and binary32 rounded after every operation
   (no -ffast-math, no contraction into fused multiply-adds: -ffp-contract=off),
   EXPT as pow, LREAL_TO_DINT rounding ties to even (nearbyint in the default
   rounding mode) and keeping the low 32 bits, DINT addition wrapping. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static int32_t wrap32(int64_t v) { return (int32_t)(uint32_t)(uint64_t)v; }

int main(int argc, char **argv) {
  int calls = argc > 1 ? atoi(argv[1]) : 1;
  int16_t i = 0;
  int32_t n = 0, d = 0, checksum = 0;
  double x = 1.5, y = 0.0, acc = 0.0;
  float single = 0.0f;
  for (int k = 0; k < calls; k++) {
    for (i = 1; i <= 1000; i++) {
      n = wrap32((int64_t)n + 1);
      y = sqrt(x * x + (double)i) / 3.0;
      x = pow(y, 1.25) + (double)(n % 17) * 0.001;
      single = (float)(x * 1.0e3);
      d = wrap32((int64_t)nearbyint(y * 1.0e7));
      checksum = wrap32((int64_t)checksum + d);
      acc = acc + (double)single / (x + 1.0);
    }
  }
  printf("MAIN.i=%d\nMAIN.n=%d\nMAIN.x=LREAL#%.17g\nMAIN.y=LREAL#%.17g\nMAIN.acc=LREAL#%.17g\n", i, n, x, y, acc);
  printf("MAIN.single=REAL#%.9g\nMAIN.d=%d\nMAIN.checksum=%d\n", single, d, checksum);
  return 0;
}
