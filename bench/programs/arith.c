/* The same computation as arith.st, with MasterTool XE semantics. */
#include "sat.h"

int main(void) {
  int32_t v[100];
  int16_t i, j, k, n = 0;
  int32_t acc = 0;
  for (i = 0; i <= 99; i++) v[i] = (int32_t)sub16(300, mul16(i, 7));
  for (k = 1; k <= 4000; k++) {
    for (j = 1; j <= 1000; j++)
      for (i = 0; i <= 99; i++)
        acc = sub32(add32(acc, mul32(v[i], 3)), (int32_t)j);
    if (internal_overflow) n = add16(n, 1);
  }
  printf("%%I0010=%d\n%%M0100=%d\n", acc, n);
  return 0;
}
