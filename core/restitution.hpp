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

} // namespace cgdem
