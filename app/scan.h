/* `rotleap scan`: the speed-accuracy trade of a deck's scene over time steps and integrators. */
#ifndef ROTLEAP_APP_SCAN_H
#define ROTLEAP_APP_SCAN_H
/* argv: the arguments after "scan".  Returns 0, 1 (a failure) or 2 (bad usage or deck). */
int rl_app_scan(int argc, char **argv);
#endif
