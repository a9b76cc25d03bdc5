/* The same computation as fbscan.st under the tecomat preset, CALLS scan
   cycles. The standard FBs as docs/tecomat.md and the catalogue define them
   (TC-FB-10/27 TON with timer-q = same-cycle, TC-FB-22/23 CTU on INT,
   TC-FB-4/16 R_TRIG); the virtual clock reads 0 ms in the first cycle and
   advances by the cycle time (10 ms) before each later one. */
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct { bool in; int32_t pt; bool q; int32_t et; bool run; int32_t start; } ton_t;
typedef struct { bool cu, r; int16_t pv; bool q; int16_t cv; bool m; } ctu_t;
typedef struct { bool clk, q, m; } rtrig_t;
typedef struct { ton_t tmr; ctu_t cnt; rtrig_t trig; int32_t edges; } cell_t;

/* TON: IN FALSE clears Q and ET; while IN is TRUE, ET counts from IN's rise
   up to PT, Q once ET reached PT (in the same call) */
static void ton(ton_t *t, int32_t now) {
  if (!t->in) { t->run = false; t->q = false; t->et = 0; return; }
  if (!t->run) { t->start = now; t->run = true; }
  int32_t elapsed = now - t->start;
  t->q = elapsed >= t->pt;
  t->et = elapsed < t->pt ? elapsed : t->pt;
}

/* CTU: R clears CV, a rising edge of CU adds one up to 32767; Q := CV >= PV */
static void ctu(ctu_t *c) {
  bool up = c->cu && !c->m;
  c->m = c->cu;
  if (c->r) c->cv = 0;
  else if (up && c->cv < 32767) c->cv++;
  c->q = c->cv >= c->pv;
}

/* R_TRIG: Q := CLK AND NOT M; M := CLK */
static void rtrig(rtrig_t *e) {
  e->q = e->clk && !e->m;
  e->m = e->clk;
}

static cell_t cells[1000];

static const char *b(bool v) { return v ? "TRUE" : "FALSE"; }

int main(int argc, char **argv) {
  int calls = argc > 1 ? atoi(argv[1]) : 1;
  int32_t cyc = 0, resets = 0, late = 0;
  int16_t j = 0;
  bool x = false;
  for (int k = 0; k < calls; k++) {
    int32_t now = k * 10;
    cyc = cyc + 1;
    for (j = 0; j <= 999; j++) {
      cell_t *c = &cells[j];
      c->tmr.in = !c->tmr.q;
      c->tmr.pt = (int32_t)(j % 13) * 7 + 15;
      ton(&c->tmr, now);
      if (c->tmr.et > 50) late++;
      x = c->tmr.q ^ ((cyc + j) % 5 == 0);
      c->trig.clk = x;
      rtrig(&c->trig);
      if (c->trig.q) c->edges++;
      c->cnt.cu = c->trig.q;
      c->cnt.r = c->cnt.q;
      c->cnt.pv = (int16_t)(j % 50 + 1);
      ctu(&c->cnt);
      if (c->cnt.q) resets++;
    }
  }
  for (int i = 0; i < 1000; i++) {
    cell_t *c = &cells[i];
    printf("MAIN.cells[%d].tmr.IN=%s\nMAIN.cells[%d].tmr.PT=T#%dms\nMAIN.cells[%d].tmr.Q=%s\nMAIN.cells[%d].tmr.ET=T#%dms\n",
           i, b(c->tmr.in), i, c->tmr.pt, i, b(c->tmr.q), i, c->tmr.et);
    printf("MAIN.cells[%d].cnt.CU=%s\nMAIN.cells[%d].cnt.R=%s\nMAIN.cells[%d].cnt.PV=%d\nMAIN.cells[%d].cnt.Q=%s\nMAIN.cells[%d].cnt.CV=%d\n",
           i, b(c->cnt.cu), i, b(c->cnt.r), i, c->cnt.pv, i, b(c->cnt.q), i, c->cnt.cv);
    printf("MAIN.cells[%d].trig.CLK=%s\nMAIN.cells[%d].trig.Q=%s\nMAIN.cells[%d].edges=%d\n",
           i, b(c->trig.clk), i, b(c->trig.q), i, c->edges);
  }
  printf("MAIN.j=%d\nMAIN.cyc=%d\nMAIN.x=%s\nMAIN.resets=%d\nMAIN.late=%d\n", j, cyc, b(x), resets, late);
  return 0;
}
