// The map of docs/model.md §7: for six miniblocks, eps from 0.05 to the stall
// boundary (1/3), the full model's mean speed and diffusion constant against the first-
// and second-order theory and the exact quasi-static result, as TSV on stdout (minutes;
// run under nice). Plot with tools/plot_long_time_map.py.
#include <cstdio>

#include "long_time_simulation.hpp"

using namespace long_time_test;

int main() {
  std::printf("renewal\teps\tV_sim\tV_err\tV_1\tV_2\tV_qs\tD_sim\tD_err\tD_1\tD_2\tD_qs\n");
  for (const char* renewal : {"poisson", "periodic"})
    for (double eps : {0.05, 0.1, 0.15, 0.2, 0.25, 0.28, 0.3, 0.32}) {
      const Parameters p = flat(6, eps, renewal);
      const Motion sim = simulate_full(p, 32768, 20, 200);
      const LongTimeMotion first = long_time_motion(p, MotionTheory::first_order);
      const LongTimeMotion second = long_time_motion(p, MotionTheory::second_order);
      const LongTimeMotion exact = long_time_motion(p, MotionTheory::quasi_static);
      std::printf("%s\t%.4f\t%.6e\t%.3e\t%.6e\t%.6e\t%.6e\t%.6e\t%.3e\t%.6e\t%.6e\t%.6e\n", renewal,
                  landmarks(p).coupling_eps, sim.mean_speed.value, sim.mean_speed.error, first.mean_speed,
                  second.mean_speed, exact.mean_speed, sim.diffusion.value, sim.diffusion.error, first.diffusion,
                  second.diffusion, exact.diffusion);
      std::fflush(stdout);
    }
}
