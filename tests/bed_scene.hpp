#pragma once
// A scene shared by the regression reference and the MPI tests (CGDEM_SHARED_DIR comes from CMake).
namespace cgdem::testing {

// The shared 10k bed under a floor that rises at 5 cm/s: contacts close and open, lists are rebuilt and
// the store reordered within a few hundred steps; periodic in x and y, so particles also cross the
// periodic faces and, on several MPI ranks, the ranks' boundaries.
inline const char* kBedScene =
    R"(domain: {lo: [0, 0, 0], hi: [0.02031, 0.02031, 0.04], periodic: [true, true, false]}
gravity: [0, 0, -9.81]
materials:
  beads: {density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.3, restitution: 0.9, friction: 0.3}
contact: {normal: hertz, tangential: mindlin}
groups:
  - name: bed
    material: beads
    placement: {type: file, file: )" CGDEM_SHARED_DIR R"(/data/settled_bed_10k.csv}
walls:
  - name: floor
    type: plane
    material: beads
    point: [0, 0, 0]
    normal: [0, 0, 1]
    motion: {velocity: [0, 0, 0.05]}
time: {end: 0.003, step: 1.0e-5}
output: {every: 0.003, file: bed.h5}
stability: {overlap_tolerance: 0.05}
)";

} // namespace cgdem::testing
