/* The same computation as sort.st; CALLS sorts, as stref run --calls CALLS. */
#include <stdlib.h>
#include "sat.h"

int main(int argc, char **argv) {
  int calls = argc > 1 ? atoi(argv[1]) : 1;
  int16_t v[501], first = 0, middle = 0, last = 0;
  int32_t swaps = 0;
  for (int c = 0; c < calls; c++) {
    int32_t seed = 12345, n = 0;
    for (int16_t i = 1; i <= 500; i++) {
      seed = add32(mul32(seed, 1103), 12345) % 65536;
      v[i] = (int16_t)(uint16_t)(uint32_t)sub32(seed, 32768);
    }
    for (int16_t i = 1; i <= 499; i++)
      for (int16_t j = 1; j <= sub16(500, i); j++)
        if (v[j] > v[j + 1]) {
          int16_t t = v[j]; v[j] = v[j + 1]; v[j + 1] = t;
          n = add32(n, 1);
        }
    first = v[1]; middle = v[250]; last = v[500]; swaps = n;
  }
  printf("%%M0100=%d\n%%M0101=%d\n%%M0102=%d\n%%I0010=%d\n", first, middle, last, swaps);
  return 0;
}
