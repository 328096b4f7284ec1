// Cohesive and elasto-plastic laws (Chen's and Hu's JKR, Hu's capillary bridges, DMT,
// Thakur's linear EEPA) with the rolling-resistance variants the source papers use.
#include "drivers/physics_factory.hpp"
#include "models/capillary_bridge.hpp"
#include "models/dmt.hpp"
#include "models/hertz_tsuji.hpp"
#include "models/jkr_full.hpp"
#include "models/linear_eepa.hpp"
#include "models/mindlin_tangential.hpp"
#include "models/rolling_resistance.hpp"

using namespace cgdem::models;
CGDEM_DEFINE_PHYSICS(make_jkr, ContactLaw<JkrFull, NoAdhesion, NoFriction, NoRolling>)
CGDEM_DEFINE_PHYSICS(make_jkr_mindlin, ContactLaw<JkrFull, NoAdhesion, MindlinTangential, NoRolling>)
CGDEM_DEFINE_PHYSICS(make_jkr_mindlin_sd, ContactLaw<JkrFull, NoAdhesion, MindlinTangential, RollingSpringDashpot>)
CGDEM_DEFINE_PHYSICS(make_hertz_dmt_mindlin, ContactLaw<HertzTsuji, Dmt, MindlinTangential, NoRolling>)
CGDEM_DEFINE_PHYSICS(make_hertz_capillary_mindlin, ContactLaw<HertzTsuji, CapillaryBridge, MindlinTangential, NoRolling>)
CGDEM_DEFINE_PHYSICS(make_hertz_capillary, ContactLaw<HertzTsuji, CapillaryBridge, NoFriction, NoRolling>)
CGDEM_DEFINE_PHYSICS(make_eepa_mindlin, ContactLaw<LinearEepa, NoAdhesion, MindlinTangential, NoRolling>)
CGDEM_DEFINE_PHYSICS(make_eepa_mindlin_ct, ContactLaw<LinearEepa, NoAdhesion, MindlinTangential, RollingConstantTorque>)
