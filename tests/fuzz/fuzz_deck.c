/* libFuzzer target for the deck parser: the input is a deck file, and its first line is also
 * offered as a --set override.  Any crash, hang, leak or sanitizer report is a bug.
 * Build and run with tests/fuzz/run_fuzz.sh. */
#include "../../app/deck.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  char path[64];
  snprintf(path, sizeof path, "/tmp/rotleap-fuzz-%d.ini", (int)getpid());
  FILE *f = fopen(path, "wb");
  if (!f) return 0;
  fwrite(data, 1, size, f);
  fclose(f);
  char set[256] = "";
  size_t n = 0;
  while (n < size && n < sizeof set - 1 && data[n] != '\n') { set[n] = data[n] ? (char)data[n] : ' '; n++; }
  set[n] = '\0';
  char *sets[1] = {set};
  FILE *err = fopen("/dev/null", "w");
  rl_deck d;
  rl_deck_load(path, sets, n > 0 ? 1 : 0, &d, err);
  fclose(err);
  remove(path);
  return 0;
}
