/* The same computation as scan.st: CALLS module calls. A channel's
   arithmetic stays within INT (at most 5 * 1008 + 1499 + 15) and never
   saturates; COUNT does, at 32767. */
#include <stdlib.h>
#include "sat.h"

int main(int argc, char **argv) {
  int calls = argc > 1 ? atoi(argv[1]) : 1;
  int16_t count = 0, inp = 0, ch[1500] = {0};
  uint16_t flags = 0;
  int32_t total = 0, sum = 0;
  for (int c = 0; c < calls; c++) {
    count = add16(count, 1);
    int16_t t = count % 16;
    inp = sub16(mul16(t, t), 100);
    total = add32(total, (int32_t)inp);
    flags ^= (1u << 3);
    if (t == 0) flags ^= 0x00F0;
    int32_t s = 0;
    for (int16_t k = 0; k <= 1499; k++) {
      ch[k] = add16(add16(mul16(ch[k], 5), k), t) % 1009;
      s = add32(s, (int32_t)ch[k]);
    }
    sum = s;
  }
  printf("%%M0200=%d\n%%M0201=%d\n%%M0202=%d\n%%I0020=%d\n%%I0021=%d\n", count, inp, (int)(int16_t)flags, total, sum);
  for (int k = 0; k < 1500; k++) printf("%%M%04d=%d\n", 300 + k, ch[k]);
  return 0;
}
