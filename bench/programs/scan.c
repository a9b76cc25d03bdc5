/* The same computation as scan.st: CALLS module calls. */
#include <stdlib.h>
#include "sat.h"

int main(int argc, char **argv) {
  int calls = argc > 1 ? atoi(argv[1]) : 1;
  int16_t count = 0, inp = 0;
  uint16_t flags = 0;
  int32_t total = 0;
  for (int c = 0; c < calls; c++) {
    count = add16(count, 1);
    int16_t t = count % 16;
    inp = sub16(mul16(t, t), 100);
    total = add32(total, (int32_t)inp);
    flags ^= (1u << 3);
    if (t == 0) flags ^= 0x00F0;
  }
  printf("%%M0200=%d\n%%M0201=%d\n%%M0202=%d\n%%I0020=%d\n", count, inp, (int)(int16_t)flags, total);
  return 0;
}
