// Direct force scaling sakai (models/scaling/direct_force_scaling.hpp) around Hertz-Mindlin, JKR-Mindlin
// and Hertz with capillary bridges (Hu 2022's validation laws); registered as "<law>@sakai".
#include "drivers/physics_factory.hpp"
#include "models/capillary_bridge.hpp"
#include "models/hertz_tsuji.hpp"
#include "models/jkr_full.hpp"
#include "models/mindlin_tangential.hpp"
#include "models/scaling/direct_force_scaling.hpp"

using namespace cgdem::models;
using cgdem::models::scaling::DirectForceScaling;
using Method = cgdem::models::scaling::Sakai;
CGDEM_DEFINE_PHYSICS(
    make_hertz_mindlin_sakai,
    DirectForceScaling<Method, ContactLaw<HertzTsuji, NoAdhesion, MindlinTangential, NoRolling>>)
CGDEM_DEFINE_PHYSICS(
    make_jkr_mindlin_sakai,
    DirectForceScaling<Method, ContactLaw<JkrFull, NoAdhesion, MindlinTangential, NoRolling>>)
CGDEM_DEFINE_PHYSICS(
    make_hertz_capillary_sakai,
    DirectForceScaling<Method, ContactLaw<HertzTsuji, CapillaryBridge, NoFriction, NoRolling>>)
