/* The same computation as filter.st. */
#include "sat.h"

static float smooth(float sample, float previous, float gain) {
  return addf(previous, mulf(subf(sample, previous), gain));
}

int main(void) {
  float y = 0.0f;
  for (int16_t k = 1; k <= 80; k++)
    for (int16_t j = 1; j <= 1000; j++)
      for (int16_t i = 1; i <= 1000; i++)
        y = smooth((float)(int16_t)(i % 100), y, 0.125f);
  printf("%%F0010=%.9g\n", y);
  return 0;
}
