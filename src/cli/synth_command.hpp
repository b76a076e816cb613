// `slidespec synth`: a synthetic displacement-sensor record of a simulated slider, to try
// analyze on; paper fig6 writes its record through it.
#pragma once

#include <string>

#include "cli/command.hpp"
#include "slidespec/analysis.hpp"

namespace slidespec::cli {

/// synth's options, as parsed.
struct SynthOptions {
  ModelOptions model;                    ///< --case, --set, --params
  SensorRequest sensor;                  ///< sampling, duration, seed, load point
  std::string resolution, sensor_noise;  ///< lengths, bare in m or with a unit (0.5um)
  double strokes = 0;                    ///< with stroke_length
  std::string stroke_length;             ///< bare in m or with a unit
  double dwell = 0;                      ///< [s]
  std::string program;                   ///< F1:T1,F2:T2,...
  std::string units = "um";              ///< of the x column
  std::string out = "record";            ///< PREFIX of PREFIX.csv
};

/// Writes OUT.csv, the record `options` ask for, and says on stderr how to analyse it.
/// Bad input throws InputError before the file is written.
void synthesize(const SynthOptions& options);

}  // namespace slidespec::cli
