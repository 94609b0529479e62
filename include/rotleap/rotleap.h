/* rotleap — molecular dynamics of rigid molecules with Omelyan's revised angular-momentum
 * leapfrog.  Umbrella header. */
#ifndef ROTLEAP_H
#define ROTLEAP_H
#define ROTLEAP_VERSION "0.1.0"
#include "rotleap/error.h"
#include "rotleap/units.h"
#include "rotleap/geometry.h"
#include "rotleap/rotation.h"
#include "rotleap/system.h"
#include "rotleap/forces.h"
#include "rotleap/integrator.h"
#include "rotleap/stepops.h"
#include "rotleap/molecule.h"
#include "rotleap/catalog.h"
#include "rotleap/terms.h"
#include "rotleap/forcefield.h"
#include "rotleap/ewald.h"
#include "rotleap/observables.h"
#include "rotleap/io.h"
#include "rotleap/run.h"
#endif
