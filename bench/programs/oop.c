/* The same computation as oop.st under the nexto preset, CALLS scan cycles of
   1000 calls: SHAPE with two derived types whose AREA is reached through a
   table of functions (a virtual call), DINT arithmetic wrapping.
   The pointers print as the addresses of stref's documented memory model
   (docs/nexto.md, "Pointers and the memory model"): the program instance
   MAIN at 16#4000_0000, its variables in declaration order, each aligned to
   its size; an instance holds its base's variables, then its own (here 3
   DINTs: 12 bytes). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static int32_t wrap32(int64_t v) { return (int32_t)(uint32_t)(uint64_t)v; }

struct shape;
typedef int32_t (*area_fn)(struct shape *, int32_t);
typedef struct shape { const area_fn *vtable; int32_t calls, last, own; } shape_t;

static int32_t square_area(shape_t *s, int32_t k) {
  s->own = (s->own + k) % 1000;
  s->calls = wrap32((int64_t)s->calls + 1);
  s->last = wrap32((int64_t)s->own * s->own);
  return s->last;
}

static int32_t circle_area(shape_t *s, int32_t k) {
  s->own = (s->own * 3 + k) % 997;
  s->calls = wrap32((int64_t)s->calls + 1);
  s->last = wrap32((int64_t)3 * s->own * s->own - k);
  return s->last;
}

static const area_fn square_vt[1] = {square_area};
static const area_fn circle_vt[1] = {circle_area};

#define BASE 0x40000000u

int main(int argc, char **argv) {
  int calls = argc > 1 ? atoi(argv[1]) : 1;
  shape_t squares[2] = {{square_vt, 0, 0, 1}, {square_vt, 0, 0, 1}};
  shape_t circles[2] = {{circle_vt, 0, 0, 2}, {circle_vt, 0, 0, 2}};
  shape_t *shapes[4] = {0, 0, 0, 0};
  uint32_t addr[4] = {0, 0, 0, 0}; /* the model's address of each shapes[] */
  shape_t *current = 0;
  uint32_t current_addr = 0;
  int16_t i = 0;
  int32_t n = 0, total = 0;
  for (int c = 0; c < calls; c++) {
    if (n == 0) {
      shapes[0] = &squares[0]; addr[0] = BASE + 0;
      shapes[1] = &circles[0]; addr[1] = BASE + 24;
      shapes[2] = &squares[1]; addr[2] = BASE + 12;
      shapes[3] = &circles[1]; addr[3] = BASE + 36;
    }
    for (i = 0; i <= 999; i++) {
      n = wrap32((int64_t)n + 1);
      int j = (n * 7 + n / 5) % 4;
      current = shapes[j];
      current_addr = addr[j];
      total = wrap32((int64_t)total + current->vtable[0](current, n % 13));
    }
  }
  for (int j = 0; j < 2; j++)
    printf("MAIN.squares[%d].calls=%d\nMAIN.squares[%d].last=%d\nMAIN.squares[%d].side=%d\n",
           j, squares[j].calls, j, squares[j].last, j, squares[j].own);
  for (int j = 0; j < 2; j++)
    printf("MAIN.circles[%d].calls=%d\nMAIN.circles[%d].last=%d\nMAIN.circles[%d].radius=%d\n",
           j, circles[j].calls, j, circles[j].last, j, circles[j].own);
  for (int j = 0; j < 4; j++) printf("MAIN.shapes[%d]=%u\n", j, addr[j]);
  printf("MAIN.current=%u\nMAIN.i=%d\nMAIN.n=%d\nMAIN.total=%d\n", current_addr, i, n, total);
  (void)current;
  return 0;
}
