// A fit through the instrument (DESIGN §6): the reading of each sample predicted as the model
// averaged over the source and detector apertures, by the quadrature the virtual instrument
// integrates with (gonio/forward_model.h). The objective (objective.h) sums a sample's nodes:
// its value and its derivatives are weighted sums of the terms' own, so one code path serves
// a fit with an instrument and without (one node at the nominal directions, weight 1).
//
// Where the aperture average equals the nominal value (a smooth diffuse floor, far from a
// lobe), a sample keeps its one nominal node: the full quadrature there changes the prediction
// by less than kNominalTolerance of it, far below any instrument's noise, and would cost tens
// of evaluations where one suffices. Which samples need the quadrature, and how many points it
// has (the lobe-width rule), depends on the model: the fit builds the nodes at its current point
// and builds them again at its optimum until they no longer change (fit_composition.h).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "fitters/fit_samples.h"
#include "gonio/forward_model.h"
#include "gonio/instrument.h"
#include "models/registry.h"

namespace brdf::fitters {

// Relative change of a sample's predicted value by the aperture average below which the sample
// keeps its nominal node.
inline constexpr double kNominalTolerance = 1e-5;

struct SampleNodes {
  std::vector<size_t> first;  // sample k's nodes are nodes[first[k], first[k + 1])
  std::vector<gonio::ReadingNode> nodes;
  size_t averaged = 0;         // samples given the aperture quadrature
  int points_per_reading = 1;  // that quadrature's points

  // Same samples averaged with the same quadrature.
  bool SameLayout(const SampleNodes& other) const {
    return first == other.first && points_per_reading == other.points_per_reading;
  }
};

// The nodes of `samples` read through `instrument`, for the quadrature and the choice of
// averaged samples at `model`.
SampleNodes InstrumentNodes(const gonio::Instrument& instrument, const Model& model,
                            const std::vector<FitSample>& samples);

// A lobe narrower than half the detector aperture's radius is seen mostly as its integral:
// every reading near it averages the whole lobe, and only the aperture's rim, where the lobe
// enters and leaves, tells its width (a blur the data can undo only as far as the noise lets
// them). kBlurredLobe is that ratio of lobe width to aperture radius.
inline constexpr double kBlurredLobe = 0.5;
// A warning when `model`'s lobe (gonio::LobeWidth) is narrower than kBlurredLobe times
// `instrument`'s detector aperture radius, naming both; empty otherwise.
std::string ApertureBlurWarning(const gonio::Instrument& instrument, const Model& model);

// The model's prediction of sample k's reading through `nodes` (its nominal value without).
Rgb PredictReading(const Model& model, const std::vector<FitSample>& samples,
                   const SampleNodes* nodes, size_t k);

}  // namespace brdf::fitters
