/* rotleap — error reporting.
 *
 * Every library call that can fail returns an int status: RL_OK (0) on success, one of the
 * codes below otherwise.  The reason is kept as a message, per thread, and read with
 * rl_last_error().  The library never prints and never exits. */
#ifndef ROTLEAP_ERROR_H
#define ROTLEAP_ERROR_H

#ifdef __cplusplus
extern "C" {
#endif

enum {
  RL_OK = 0,
  RL_EINVAL = 1,    /* an argument is out of its domain (h <= 0, J <= 0, ...)   */
  RL_ENOMEM = 2,    /* allocation failed                                        */
  RL_ENONFINITE = 3,/* a NaN or Inf was given or produced                       */
  RL_EORTHO = 4,    /* an orientation is not orthonormal / a unit vector is not unit */
  RL_ENOCONV = 5,   /* an iteration did not converge                            */
  RL_EFORCE = 6,    /* the force provider reported an error                     */
  RL_ESTATE = 7     /* call made in the wrong state (e.g. step before init)     */
};

/* Message of the last failing call in this thread ("" if none). */
const char *rl_last_error(void);
/* Name of a status code ("RL_EINVAL", ...). */
const char *rl_strerror(int status);

/* Used by library modules and force providers: record a message and return `status`. */
int rl_error(int status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Prefix the current message with a formatted context: "<context>: <previous message>". */
int rl_error_wrap(int status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
void rl_error_clear(void);

#ifdef __cplusplus
}
#endif
#endif
