#pragma once
// Damping coefficients that give a wanted coefficient of restitution (docs/physics.md section 2).
//
// Every normal law damps with c_n = eta sqrt(m* k_ref), k_ref its reference stiffness (2 E* a for Hertz and
// JKR, k_n for the linear spring, k1 for EEPA), and the tangential spring with c_t = eta sqrt(m* k_t).
// For a linear spring eta = 2 |beta|, beta = ln e / sqrt(ln^2 e + pi^2), gives e exactly. For Hertz the
// collision obeys m* delta'' = -(4/3) E* sqrt(R*) delta^1.5 - eta sqrt(2 m* E* sqrt(R*)) delta^(1/4) delta';
// with delta = D x and t = T tau, T^2 = 3 m* / (4 E* sqrt(R*) sqrt(D)), it becomes
//   x'' + sqrt(3/2) eta x^(1/4) x' + x^(3/2) = 0,  x(0) = 0, x'(0) = 1,
// free of size, mass, stiffness and impact speed: e depends on eta alone, and one root solve per value of e
// gives the eta that a Hertz contact needs. Two forms of the end of the contact:
//   clamped   (Hertz-Tsuji, DMT on Hertz): the normal force is held at >= 0, so the surfaces part when the
//             force first returns to zero and move freely afterwards; e = -x' there;
//   unclamped (full JKR): the damper may pull; the contact lasts until x = 0; e = -x' there (the JKR law at
//             impact speeds far above its sticking velocity). Here Tsuji's eta = 2 sqrt(5/6) |beta| is
//             exact; with the clamp it is not (e = 0.5 gives 0.550), hence the solve.
//
// Adhesive laws (JKR, DMT) lose the work of adhesion on top of the damper's share, and the damper acts while
// the adhesion works, so their rebound depends on the impact speed (docs/physics.md 2). In the pair's natural
// JKR scales (u, F_c of models/jkr_relation.hpp, time T = sqrt(m* u / F_c)), with delta = u d and x = a /
// a_c, the collision is free of size, mass and stiffness; the impact speed enters as s = v / v_stick, v_stick
// = sqrt(2 W_s / m*) (W_s the JKR work of adhesion from A to S, 22.5163 (gamma^5 R*^4 / E*^2)^(1/3)):
//   JKR  d'' = -(4/9 x^3 - 4/3 x^1.5) - sqrt(2/3) eta sqrt(x) d',  d = x^2 - 2 sqrt(x), snapped in at d = 0,
//        until d falls below the separation overlap on the way out (delta_S, delta_C or 0);
//   DMT  d'' = -max(0, 4/9 d^1.5 + sqrt(2/3) eta d^(1/4) d') + 4/3 while d >= 0 (Hertz held >= 0, then the
//        constant pull 4 pi gamma R* = 4/3 F_c),
// from d = 0, d' = s V_stick (V_stick = sqrt(2 W_s / (F_c u)) = 1.49248...), e = -d' at the end / d'(0).
// So one root solve per (e, law, s) gives the eta with which the pair rebounds with e at s v_stick
// (contact.restitution_speed_ratio), whatever its size.
// Host only.
#include <string>

namespace cgdem {

enum class HertzContactEnd { Clamped, Unclamped };

// beta(e) = ln e / sqrt(ln^2 e + pi^2) <= 0 (0 for e >= 1).
double restitution_beta(double restitution);

// Restitution of the dimensionless damped Hertz collision with damping eta >= 0 (forward map, for tests
// and plots). Accurate to about 1e-9.
double hertz_restitution(double eta, HertzContactEnd end);

// The eta in (0, inf) that gives `restitution` in (0, 1] (0 for e = 1): a root of hertz_restitution for the
// clamped form (cached per e, safe to call from several host threads), Tsuji's closed form for the
// unclamped one.
double hertz_damping_for_restitution(double restitution, HertzContactEnd end);

// The adhesive collisions above; the JKR forms differ only in where a bonded pair separates.
enum class AdhesiveCollision { JkrDeltaS, JkrPullOff, JkrContactLoss, Dmt };

// Dimensionless sticking velocity sqrt(2 W_s / (F_c u)).
double jkr_sticking_speed();

// Restitution of the dimensionless adhesive collision with damping eta >= 0 at impact speed s v_stick (s >
// 0); 0 if the pair never separates (it sticks). Accurate to about 1e-7.
double adhesive_restitution(double eta, AdhesiveCollision law, double speed_ratio);

// The eta >= 0 with which the adhesive collision at s v_stick rebounds with `restitution` (cached, safe to
// call from several host threads). 0 when even the undamped collision rebounds slower than that (adhesion
// alone takes more than 1 - e^2 of the energy at this speed).
double adhesive_damping_for_restitution(double restitution, AdhesiveCollision law, double speed_ratio);

} // namespace cgdem
