/* A main for the fuzz targets without libFuzzer: feeds every file named on the command line, and
 * every file in every directory named, to LLVMFuzzerTestOneInput once.  CTest runs it over the
 * checked-in corpora (tests/fuzz/corpus*) in both builds, so that each input libFuzzer found
 * interesting is replayed under the Release and sanitizer builds in seconds. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int feed(const char *path)
{
  FILE *f = fopen(path, "rb");
  if (!f) { fprintf(stderr, "cannot open %s\n", path); return 1; }
  size_t cap = 4096, n = 0, got;
  uint8_t *b = malloc(cap);
  while (b && (got = fread(b + n, 1, cap - n, f)) > 0) {
    n += got;
    if (n == cap) {
      uint8_t *nb = realloc(b, cap *= 2);
      if (!nb) { free(b); b = NULL; }
      b = nb;
    }
  }
  fclose(f);
  if (!b) { fprintf(stderr, "out of memory for %s\n", path); return 1; }
  LLVMFuzzerTestOneInput(b, n);
  free(b);
  return 0;
}

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

int main(int argc, char **argv)
{
  long inputs = 0;
  int bad = 0;
  for (int k = 1; k < argc; k++) {
    struct stat st;
    if (stat(argv[k], &st) != 0) { fprintf(stderr, "no such file or directory: %s\n", argv[k]); bad = 1; continue; }
    if (!S_ISDIR(st.st_mode)) { bad |= feed(argv[k]); inputs++; continue; }
    DIR *d = opendir(argv[k]);
    char **names = NULL;
    size_t n = 0;
    for (struct dirent *e; d && (e = readdir(d));) {
      if (e->d_name[0] == '.') continue;
      char **nn = realloc(names, sizeof *names * (n + 1));
      if (!nn) break;
      names = nn;
      names[n] = malloc(strlen(argv[k]) + strlen(e->d_name) + 2);
      if (names[n]) sprintf(names[n++], "%s/%s", argv[k], e->d_name);
    }
    if (d) closedir(d);
    qsort(names, n, sizeof *names, by_name);
    for (size_t i = 0; i < n; i++) {
      bad |= feed(names[i]);
      free(names[i]);
      inputs++;
    }
    free(names);
  }
  printf("replayed %ld inputs\n", inputs);
  return bad || inputs == 0;
}
