/* The same computation as convert.st. */
#include "sat.h"

int main(void) {
  int32_t acc = 0;
  uint16_t wa = 0;
  for (int16_t k = 1; k <= 150; k++)
    for (int16_t j = 1; j <= 1000; j++)
      for (int16_t i = -500; i <= 499; i++) {
        float x = mulf((float)i, 1.5f);
        int32_t d = real_to_dint(x);
        uint8_t b = (uint8_t)(uint32_t)d;
        wa ^= (uint16_t)b;
        acc = add32(acc, (int32_t)(int16_t)(uint16_t)(uint32_t)mul32(d, 1000));
      }
  printf("%%I0011=%d\n%%M0101=%d\n", acc, (int)(int16_t)wa);
  return 0;
}
