/* The same computation as pointers.st under the nexto preset, CALLS scan
   cycles of 1000 steps along a ring of 64 nodes linked by pointers, DINT
   arithmetic wrapping. The pointers print as the addresses of stref's
   documented memory model (docs/nexto.md, "Pointers and the memory model"):
   MAIN at 16#4000_0000, its variables in declaration order each aligned to
   its size; NODE = value (DINT, offset 0), weight (INT, 4), next (a pointer,
   8): 12 bytes. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static int32_t wrap32(int64_t v) { return (int32_t)(uint32_t)(uint64_t)v; }

typedef struct node { int32_t value; int16_t weight; struct node *next; } node_t;

#define BASE 0x40000000u
static node_t nodes[64];
static uint32_t model(const void *q) { /* the model's address of a node or its value */
  return BASE + 12u * (uint32_t)((const node_t *)q - nodes);
}

int main(int argc, char **argv) {
  int calls = argc > 1 ? atoi(argv[1]) : 1;
  node_t *p = 0;
  int32_t *pv = 0;
  int16_t i = 0;
  int32_t steps = 0, total = 0;
  for (int c = 0; c < calls; c++) {
    if (steps == 0) {
      for (i = 0; i <= 63; i++) {
        nodes[i].value = (int32_t)i * 3;
        nodes[i].weight = (int16_t)(i % 5 + 1);
        nodes[i].next = &nodes[(i * 5 + 1) % 64];
      }
      p = &nodes[0];
    }
    for (i = 1; i <= 1000; i++) {
      steps = wrap32((int64_t)steps + 1);
      total = wrap32((int64_t)total + (int64_t)p->value * p->weight);
      pv = &p->value;
      *pv = (*pv + steps) % 1000;
      p = p->next;
    }
  }
  for (int j = 0; j < 64; j++)
    printf("MAIN.nodes[%d].value=%d\nMAIN.nodes[%d].weight=%d\nMAIN.nodes[%d].next=%u\n",
           j, nodes[j].value, j, nodes[j].weight, j, model(nodes[j].next));
  printf("MAIN.p=%u\nMAIN.pv=%u\nMAIN.i=%d\nMAIN.steps=%d\nMAIN.total=%d\n",
         p ? model(p) : 0, pv ? model((const node_t *)pv) : 0, i, steps, total);
  return 0;
}
