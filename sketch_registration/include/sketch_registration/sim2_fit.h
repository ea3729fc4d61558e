// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Closed-form least-squares similarity fits p = s R c + t (Umeyama-style, in 2D), the transform
// distance d_T of the paper, and the Fourier shape descriptor used to filter correspondence
// polygons.
#pragma once

#include <vector>

#include "efs_common/sim2.h"
#include "sketch_registration/types.h"

namespace efs::registration {

struct Sim2Fit {
  Sim2 T_world_sketch;
  double rms_residual_m = 0.0;  ///< world frame
  bool ok = false;              ///< false for fewer than 2 points or a degenerate source
};

/// Least squares over pairs (c_i -> p_i) with optional weights. With `reflected` the linear part
/// is s R diag(1,-1). The scale is clamped into [scale_min, scale_max] (t refit for it), which is
/// the bounded-scale step of Scale-ICP; pass 0 / +inf for the unconstrained paper formula.
Sim2Fit fitSim2(const Points2d& c_sketch, const Points2d& p_world, bool reflected,
                double scale_min = 0.0, double scale_max = 1e300,
                const std::vector<double>* weights = nullptr);

/// As fitSim2, with a stretch of at most `stretch_max` fitted too: a drawing whose aspect ratio
/// is off.
/// Alternates the similarity fit of the stretched sketch points with the least-squares symmetric
/// map given the rotation; starts from `start`'s stretch (none if null). Where the stretch is not
/// fitted (stretch_max <= 1, or nearly collinear points that leave it unobservable) it stays as
/// started and only the similarity is fitted.
Sim2Fit fitStretchedSim2(const Points2d& c_sketch, const Points2d& p_world, bool reflected,
                         double scale_min, double scale_max, double stretch_max,
                         const std::vector<double>* weights = nullptr, const Sim2* start = nullptr);

/// Fits both the proper and the reflected transform and keeps the smaller residual; when the two
/// are within `ambiguity_ratio` of each other (collinear points), `prefer_reflected` decides.
Sim2Fit fitSim2Either(const Points2d& c_sketch, const Points2d& p_world, bool prefer_reflected,
                      double ambiguity_ratio = 0.05);

/// Paper d_T = l1 |t_i - t_j| + l2 theta(R_i, R_j) + l3 |s_i - s_j|; transforms of different
/// handedness are infinitely far apart.
struct TransformDistanceWeights {
  double lambda_t = 5.0;
  double lambda_r = 10.0;
  double lambda_s = 1.0;
};
double transformDistance(const Sim2& a, const Sim2& b, const TransformDistanceWeights& w);
/// A lower bound of transformDistance from the translations alone: lambda_t times the larger
/// coordinate difference, a fraction of the cost. DBSCAN asks up to ~10^6 pairs a frame whether
/// they lie within eps, and most lie far apart. 0 when a weight is negative (no bound holds).
double transformDistanceLowerBound(const Sim2& a, const Sim2& b, const TransformDistanceWeights& w);

/// Similarity-invariant Fourier descriptor of a closed polygon (vertices in order): magnitudes
/// |Z_k| / |Z_1| for k = 2..K-1 of the DFT Z of the complex vertex sequence (Z_0 = translation is
/// dropped, dividing by |Z_1| removes scale, magnitudes remove rotation and the start vertex).
std::vector<double> fourierDescriptor(const Points2d& polygon, int max_components = 8);
/// Euclidean distance between two descriptors (shorter one zero-padded).
double fourierDistance(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace efs::registration
