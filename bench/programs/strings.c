/* The same computation as strings.st under the tecomat preset, CALLS scan
   cycles of 1000 iterations. The string functions as src/Stref/IEC/Standard.hs
   and docs/tecomat.md define them (TC-STR-6..11, 13, 15..18): positions are
   1-based; a window (P, L) on a string of n characters starts at P cut to
   1..n+1 and takes L cut to 0..n+1-start characters; INSERT puts IN2 at
   position P; a result is cut to the 80 characters of its destination. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CAP 80

typedef struct { int len; char c[CAP + 1]; } str_t;

/* the window of (pos, len) on a string of n characters: 0-based start, count */
static void window(int n, int pos, int len, int *start, int *count) {
  int s = pos < 1 ? 1 : pos > n + 1 ? n + 1 : pos;
  int k = len < 0 ? 0 : len > n + 1 - s ? n + 1 - s : len;
  *start = s - 1;
  *count = k;
}

/* store characters into a STRING[80]: the first 80 are kept */
static void store(str_t *dst, const char *src, int n) {
  if (n > CAP) n = CAP;
  memmove(dst->c, src, n);
  dst->len = n;
  dst->c[n] = 0;
}

static void mid(str_t *dst, const str_t *in, int l, int p) {
  int s, k;
  window(in->len, p, l, &s, &k);
  char tmp[CAP + 1];
  memcpy(tmp, in->c + s, k);
  store(dst, tmp, k);
}

static void concat(str_t *dst, const str_t *a, const str_t *b) {
  char tmp[2 * CAP + 2];
  memcpy(tmp, a->c, a->len);
  memcpy(tmp + a->len, b->c, b->len);
  store(dst, tmp, a->len + b->len);
}

static int find(const str_t *a, const char *b, int bl) {
  if (bl == 0) return 1;
  for (int i = 0; i + bl <= a->len; i++)
    if (memcmp(a->c + i, b, bl) == 0) return i + 1;
  return 0;
}

static void insert(str_t *dst, const str_t *a, const char *b, int bl, int p) {
  int s, k;
  window(a->len, p, 0, &s, &k);
  char tmp[2 * CAP + 2];
  memcpy(tmp, a->c, s);
  memcpy(tmp + s, b, bl);
  memcpy(tmp + s + bl, a->c + s, a->len - s);
  store(dst, tmp, a->len + bl);
}

static void delete(str_t *dst, const str_t *in, int l, int p) {
  int s, k;
  window(in->len, p, l, &s, &k);
  char tmp[CAP + 1];
  memcpy(tmp, in->c, s);
  memcpy(tmp + s, in->c + s + k, in->len - s - k);
  store(dst, tmp, in->len - k);
}

int main(int argc, char **argv) {
  int calls = argc > 1 ? atoi(argv[1]) : 1;
  static const char *words[5] = {"alpha", "beta", "gamma", "delta", "omega"};
  str_t txt, piece = {0, ""};
  const char *init = "the quick brown fox jumps over the lazy dog";
  store(&txt, init, (int)strlen(init));
  int16_t i = 0, pos = 0;
  int32_t iterations = 0, found = 0, inserted = 0, cut = 0, total = 0;
  for (int k = 0; k < calls; k++) {
    for (i = 1; i <= 1000; i++) {
      iterations++;
      mid(&piece, &txt, i % 9 + 1, i % 31 + 1);
      concat(&txt, &txt, &piece);
      const char *w = words[(i + 2) % 5];
      pos = (int16_t)find(&txt, w, (int)strlen(w));
      if (pos > 0) {
        found += pos;
        delete(&txt, &txt, 3, pos + 1);
      } else {
        w = words[i % 5];
        insert(&txt, &txt, w, (int)strlen(w), i % 37 + 1);
        inserted++;
      }
      if (txt.len > 60) {
        delete(&txt, &txt, txt.len - 40, i % 11 + 1);
        cut++;
      }
      total += txt.len;
    }
  }
  printf("MAIN.txt='%s'\nMAIN.piece='%s'\n", txt.c, piece.c);
  for (int w = 0; w < 5; w++) printf("MAIN.words[%d]='%s'\n", w, words[w]);
  printf("MAIN.i=%d\nMAIN.iterations=%d\nMAIN.pos=%d\nMAIN.found=%d\nMAIN.inserted=%d\nMAIN.cut=%d\nMAIN.total=%d\n",
         i, iterations, pos, found, inserted, cut, total);
  return 0;
}
