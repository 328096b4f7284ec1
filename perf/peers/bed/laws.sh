# The contact laws of the bed benchmarks as cgdem --set overrides of perf/peers/bed/bed_*.yaml (Hertz-Mindlin),
# shared by compare.sh and perf/law_cost.sh. Sourced, not run.
#   cgdem_law_settings LAW [GAMMA]   sets the array CGDEM_LAW; returns 1 for an unknown law
# LAW: hertz | jkr | dmt | capillary | eepa, optionally @hu_method1|@hu_method2|@hu_method3|@sakai: the same
# law under direct force scaling with the bed's spheres taken as coarse particles of factor 2 (their original
# is half their size; capillary without friction, as compiled). The floor is not adhesive (in.bed.lammps says why). GAMMA: the surface energy of jkr and
# dmt (default 0.05 J/m^2). jkr: bonds broken at the pull-off force as LAMMPS does.
cgdem_law_settings() {
  local law=${1%%@*} method= gamma=${2:-0.05}
  [ "$law" = "$1" ] || method=${1#*@}
  case $law in
    hertz) CGDEM_LAW=() ;;
    jkr) CGDEM_LAW=(--set contact.normal=jkr --set contact.jkr_separation=pull_off --set contact.wall_adhesion=false
                    --set materials.beads.surface_energy="$gamma") ;;
    dmt) CGDEM_LAW=(--set contact.adhesion=dmt --set contact.wall_adhesion=false
                    --set materials.beads.surface_energy="$gamma") ;;
    capillary) CGDEM_LAW=(--set contact.adhesion=capillary --set contact.wall_adhesion=false
                          --set 'materials.beads.capillary={surface_tension: 0.072, contact_angle: 0, liquid_fraction: 0.00415}') ;;
    eepa) CGDEM_LAW=(--set contact.normal=eepa --set contact.wall_adhesion=false
                     --set 'materials.beads.eepa={k1: 100, k2: 300, k_adh: 50, f0: -5.0e-6}') ;;
    *) return 1 ;;
  esac
  case $method in
    "") ;;
    # The step of the unscaled bed, above the stable limit of the scaled contact for sakai (l^2.5 stiffer):
    # the benchmark times a step, it does not follow the bed.
    hu_method1|hu_method2|hu_method3|sakai)
      CGDEM_LAW+=(--set "groups.0.coarse_grain={law: $method, factor: 2}" --set time.force_step=true)
      # Hu's capillary case is frictionless: the wrapped bridge law is compiled without a tangential spring.
      [ "$law" != capillary ] || CGDEM_LAW+=(--set contact.tangential=none) ;;
    *) return 1 ;;
  esac
}
