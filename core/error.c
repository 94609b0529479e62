/* Error messages: one buffer per thread, set by rl_error(), read by rl_last_error(). */
#include "rotleap/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static _Thread_local char last_message[16384]; /* room for messages naming paths as long as PATH_MAX */

const char *rl_last_error(void) { return last_message; }

void rl_error_clear(void) { last_message[0] = '\0'; }

int rl_error(int status, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(last_message, sizeof last_message, fmt, ap);
  va_end(ap);
  return status;
}

int rl_error_wrap(int status, const char *fmt, ...)
{
  char prev[sizeof last_message], ctx[sizeof last_message];
  memcpy(prev, last_message, sizeof prev);
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(ctx, sizeof ctx, fmt, ap);
  va_end(ap);
  snprintf(last_message, sizeof last_message, "%.8000s: %.8000s", ctx, prev[0] ? prev : rl_strerror(status));
  return status;
}

const char *rl_strerror(int status)
{
  switch (status) {
  case RL_OK: return "RL_OK";
  case RL_EINVAL: return "RL_EINVAL";
  case RL_ENOMEM: return "RL_ENOMEM";
  case RL_ENONFINITE: return "RL_ENONFINITE";
  case RL_EORTHO: return "RL_EORTHO";
  case RL_ENOCONV: return "RL_ENOCONV";
  case RL_EFORCE: return "RL_EFORCE";
  case RL_ESTATE: return "RL_ESTATE";
  default: return "RL_E?";
  }
}
