// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/traversable_region.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "efs_common/config_check.h"
#include "prior_map_tools/prior_map_error.h"

namespace efs::prior_map {

void TraversableConfig::validate() const {
  requireInRange("robot_radius_m", robot_radius_m, 0.0, 10.0);
  requireInRange("max_outer_gap_m", max_outer_gap_m, 0.0, 100.0);
  requireInRange("open_outline_gap_m", open_outline_gap_m, 0.0, 1000.0);
  requireInRange("min_region_area_m2", min_region_area_m2, 0.0, 1e6);
  requireInRange("min_enclosed_span_fraction", min_enclosed_span_fraction, 0.0, 1.0);
}

namespace {

// Everything 4-connected to the image border through non-wall pixels. The image is padded by one
// free pixel so the fill reaches around walls drawn on the border itself.
cv::Mat1b exteriorOf(const cv::Mat1b& walls) {
  cv::Mat1b padded;
  cv::copyMakeBorder(walls, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::Mat1b fill = padded.clone();
  // floodFill marks reached pixels with 128 in a copy where walls are 255 and free is 0.
  cv::floodFill(fill, cv::Point(0, 0), cv::Scalar(128), nullptr, cv::Scalar(0), cv::Scalar(0), 4);
  cv::Mat1b exterior = (fill == 128);
  return exterior(cv::Rect(1, 1, walls.cols, walls.rows)).clone();
}

// Morphological closing of the wall mask by a disc of `radius_px`, via distance transforms
// (linear time whatever the radius, unlike a kernel of that size).
cv::Mat1b closeWalls(const cv::Mat1b& walls, const cv::Mat1f& dist_to_wall, int radius_px) {
  if (radius_px <= 0) return walls.clone();
  cv::Mat1b dilated = dist_to_wall <= static_cast<float>(radius_px);
  cv::Mat1b not_dilated = ~dilated;
  if (cv::countNonZero(not_dilated) == 0) return dilated;
  cv::Mat1f dist_to_outside;
  cv::distanceTransform(dilated, dist_to_outside, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  // Eroding by one pixel less than the dilation keeps a sealed gap sealed: with discrete pixels
  // an exact-radius erosion reopens a one-pixel channel through the middle of a gap.
  cv::Mat1b closed = dist_to_outside > static_cast<float>(radius_px - 1);
  return closed | walls;
}

// Bounding box of the enclosed components of at least `min_area_px` pixels (empty if none). The
// hollow pillars of a car park enclose specks all over the drawing: counted, they made a partial
// garage sketch's two closets span the whole page, and the closets became the building.
cv::Rect enclosedSpan(const cv::Mat1b& enclosed, double min_area_px) {
  cv::Mat1i labels;
  cv::Mat stats, centroids;
  const int n = cv::connectedComponentsWithStats(enclosed, labels, stats, centroids, 8, CV_32S);
  cv::Rect span;
  for (int l = 1; l < n; ++l) {
    if (stats.at<int>(l, cv::CC_STAT_AREA) < min_area_px) continue;
    const cv::Rect r(stats.at<int>(l, cv::CC_STAT_LEFT), stats.at<int>(l, cv::CC_STAT_TOP),
                     stats.at<int>(l, cv::CC_STAT_WIDTH), stats.at<int>(l, cv::CC_STAT_HEIGHT));
    span = span.area() > 0 ? (span | r) : r;
  }
  return span;
}

// The pixels of `mask` whose 8-connected component has a pixel in `touch`.
cv::Mat1b componentsTouching(const cv::Mat1b& mask, const cv::Mat1b& touch) {
  cv::Mat1i labels;
  const int n = cv::connectedComponents(mask, labels, 8, CV_32S);
  std::vector<uint8_t> touched(static_cast<size_t>(n), 0);
  for (int r = 0; r < mask.rows; ++r)
    for (int c = 0; c < mask.cols; ++c)
      if (mask(r, c) && touch(r, c)) touched[static_cast<size_t>(labels(r, c))] = 1;
  cv::Mat1b out = cv::Mat1b::zeros(mask.size());
  for (int r = 0; r < mask.rows; ++r)
    for (int c = 0; c < mask.cols; ++c)
      if (mask(r, c) && touched[static_cast<size_t>(labels(r, c))]) out(r, c) = 255;
  return out;
}

// The triangles of the Delaunay triangulation of the strokes (one point per `step_px` square of
// ink) whose edges are all shorter than `max_edge_px`, filled: the strokes' concave hull at that
// scale, with straight chords across the gaps (a closing by a disc would bite a round notch out
// of a hall whose fourth wall is missing).
cv::Mat1b shortTriangles(const cv::Mat1b& walls, double max_edge_px, int step_px) {
  cv::Mat1b out = cv::Mat1b::zeros(walls.size());
  cv::Subdiv2D subdiv(cv::Rect(0, 0, walls.cols, walls.rows));
  int inserted = 0;
  for (int r0 = 0; r0 < walls.rows; r0 += step_px) {
    for (int c0 = 0; c0 < walls.cols; c0 += step_px) {
      const cv::Rect cell(c0, r0, std::min(step_px, walls.cols - c0),
                          std::min(step_px, walls.rows - r0));
      cv::Point at;
      double top = 0.0;
      cv::minMaxLoc(walls(cell), nullptr, &top, nullptr, &at);
      if (top <= 0.0) continue;
      subdiv.insert(cv::Point2f(static_cast<float>(c0 + at.x), static_cast<float>(r0 + at.y)));
      ++inserted;
    }
  }
  if (inserted < 3) return out;
  std::vector<cv::Vec6f> triangles;
  subdiv.getTriangleList(triangles);
  const double max_sq = max_edge_px * max_edge_px;
  const auto sq = [](const cv::Point2f& d) { return double(d.x) * d.x + double(d.y) * d.y; };
  for (const cv::Vec6f& t : triangles) {
    const cv::Point2f a(t[0], t[1]), b(t[2], t[3]), c(t[4], t[5]);
    if (sq(a - b) > max_sq || sq(b - c) > max_sq || sq(c - a) > max_sq) continue;
    const cv::Point corners[3] = {cv::Point(cvRound(a.x), cvRound(a.y)),
                                  cv::Point(cvRound(b.x), cvRound(b.y)),
                                  cv::Point(cvRound(c.x), cvRound(c.y))};
    cv::fillConvexPoly(out, corners, 3, cv::Scalar(255));
  }
  return out;
}

// The insides of the closed loops of ink that stand free of each other (a pillar drawn as a
// square), but for the loop enclosing the most: a free component counts as a loop's inside if it
// borders that one ink component alone and not the page's edge. The largest is the building's
// own outline (a cave drawn as one loop, a floor plan whose rooms border nothing else).
// They are no evidence of where the outline runs, and they are solid even where the outline is
// open, unlike islandInteriors() (below), which needs a closed outline to tell them apart.
// Seen: the Pittsburgh mine's partial drawing leaves two regions' walls out, so its strokes
// enclose nothing but the pillars, which span the page; taken for the mine, they put all 156
// guidepoints and all 6984 registration candidates in rock.
cv::Mat1b looseLoopInteriors(const cv::Mat1b& walls) {
  cv::Mat1i ink_labels, free_labels;
  const int n_ink = cv::connectedComponents(walls, ink_labels, 8, CV_32S);
  const int n_free = cv::connectedComponents(~walls, free_labels, 4, CV_32S);
  // Per free component: the one ink component it borders, kNone yet, or kNotOneLoop (several,
  // or the page's edge).
  constexpr int kNone = 0, kNotOneLoop = -1;
  std::vector<int> border_ink(static_cast<size_t>(n_free), kNone);
  std::vector<int> area(static_cast<size_t>(n_free), 0);
  const auto note = [&](int free_label, int r, int c) {
    if (!walls(r, c)) return;
    int& ink = border_ink[static_cast<size_t>(free_label)];
    const int l = ink_labels(r, c);
    if (ink == kNone)
      ink = l;
    else if (ink != l)
      ink = kNotOneLoop;
  };
  for (int r = 0; r < walls.rows; ++r) {
    for (int c = 0; c < walls.cols; ++c) {
      if (walls(r, c)) continue;
      const int f = free_labels(r, c);
      ++area[static_cast<size_t>(f)];
      if (r == 0 || c == 0 || r + 1 == walls.rows || c + 1 == walls.cols) {
        border_ink[static_cast<size_t>(f)] = kNotOneLoop;
        continue;
      }
      note(f, r - 1, c);
      note(f, r + 1, c);
      note(f, r, c - 1);
      note(f, r, c + 1);
    }
  }
  std::vector<double> enclosed_by(static_cast<size_t>(n_ink), 0.0);
  for (int f = 1; f < n_free; ++f) {
    const int ink = border_ink[static_cast<size_t>(f)];
    if (ink > 0) enclosed_by[static_cast<size_t>(ink)] += area[static_cast<size_t>(f)];
  }
  const int outline = static_cast<int>(std::max_element(enclosed_by.begin(), enclosed_by.end()) -
                                       enclosed_by.begin());
  cv::Mat1b out = cv::Mat1b::zeros(walls.size());
  for (int r = 0; r < walls.rows; ++r) {
    for (int c = 0; c < walls.cols; ++c) {
      if (walls(r, c)) continue;
      const int ink = border_ink[static_cast<size_t>(free_labels(r, c))];
      if (ink > 0 && ink != outline) out(r, c) = 255;
    }
  }
  return out;
}

// The free pixels of `interior_free` whose component borders no stroke of the outline: the inside
// of a closed loop standing free in the drawing (a pillar of a room-and-pillar mine, a service
// core), rock or a solid block, not a place to be. The outline's strokes are the ink components
// that touch `exterior`; the rooms and corridors of a floor plan border them, or border walls
// joined to them. Seen: the Pittsburgh mine's precise drawing gave 124 components and put 147 of
// its 445 guidepoints in pillars, in the guided flight's sequences.
cv::Mat1b islandInteriors(const cv::Mat1b& walls, const cv::Mat1b& exterior,
                          const cv::Mat1b& interior_free) {
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  cv::Mat1b near_exterior, near_outline;
  cv::dilate(exterior, near_exterior, kernel);
  cv::dilate(componentsTouching(walls, near_exterior), near_outline, kernel);
  return interior_free & ~componentsTouching(interior_free, near_outline);
}

}  // namespace

namespace {

/// Clearance from walls and outside, then the components large enough to keep. If none is, and
/// `fallback_footprint` is given, the same on that footprint.
TraversableRegion regionWithClearance(const std::string& name, double m_per_px,
                                      const TraversableConfig& config, TraversableRegion out,
                                      const cv::Mat1b& walls, const cv::Mat1b& interior_free,
                                      const cv::Mat1b& fallback_footprint) {
  if (cv::countNonZero(interior_free) == 0) {
    throw PriorMapError(name + ": no traversable region: the map has no free cells");
  }

  // Clearance: a pixel is traversable if the robot's disc around it touches no wall or outside.
  cv::Mat1f clearance_px;
  cv::distanceTransform(interior_free, clearance_px, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const float radius_px = static_cast<float>(config.robot_radius_m / m_per_px);
  cv::Mat1b traversable = clearance_px > radius_px;

  cv::Mat1i labels;
  cv::Mat stats, centroids;
  const int n = cv::connectedComponentsWithStats(traversable, labels, stats, centroids, 8, CV_32S);
  const double px_area = m_per_px * m_per_px;
  std::vector<std::pair<double, int>> kept;  // (area, old label)
  for (int l = 1; l < n; ++l) {
    const double a = stats.at<int>(l, cv::CC_STAT_AREA) * px_area;
    if (a >= config.min_region_area_m2) kept.emplace_back(a, l);
  }
  if (kept.empty() && !fallback_footprint.empty() &&
      cv::countNonZero(fallback_footprint & ~out.footprint) > 0) {
    out.footprint = fallback_footprint;
    out.outer_gap_closing_px = 0;
    out.outer_outline_open = true;
    return regionWithClearance(name, m_per_px, config, std::move(out), walls,
                               fallback_footprint & ~walls, cv::Mat1b());
  }
  if (kept.empty()) {
    std::ostringstream os;
    os << name << ": no traversable region large enough for the robot: "
       << "robot_radius_m = " << config.robot_radius_m << " at " << m_per_px
       << " m/px leaves no free component of at least " << config.min_region_area_m2 << " m^2";
    throw PriorMapError(os.str());
  }
  std::sort(kept.begin(), kept.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<int> relabel(n, 0);
  for (size_t i = 0; i < kept.size(); ++i) {
    relabel[kept[i].second] = static_cast<int>(i) + 1;
    out.component_area_m2.push_back(kept[i].first);
  }
  out.components = cv::Mat1i::zeros(labels.size());
  out.mask = cv::Mat1b::zeros(labels.size());
  for (int r = 0; r < labels.rows; ++r) {
    const int* src = labels.ptr<int>(r);
    int* dst = out.components.ptr<int>(r);
    uint8_t* m = out.mask.ptr<uint8_t>(r);
    for (int c = 0; c < labels.cols; ++c) {
      const int l = relabel[src[c]];
      dst[c] = l;
      m[c] = l > 0 ? 255 : 0;
    }
  }
  for (double a : out.component_area_m2) out.area_m2 += a;
  return out;
}

}  // namespace

TraversableRegion extractTraversable(const LoadedSketch& sketch, const TraversableConfig& config) {
  config.validate();
  const std::string& name = sketch.source_path;
  const double m_per_px = sketch.frame.m_per_px;
  const cv::Mat1b& walls = sketch.wall_mask;
  if (walls.empty()) throw PriorMapError(name + ": empty sketch");
  if (cv::countNonZero(walls) == static_cast<int>(walls.total())) {
    throw PriorMapError(name + ": no traversable region: the image is entirely wall (all black)");
  }

  TraversableRegion out;
  cv::Mat1b interior_free;
  cv::Mat1b fallback_footprint;  // drawings: the ink's convex hull, if the outline leaves nothing
  if (sketch.kind == SketchKind::kOccupancyGrid) {
    interior_free = ~(walls | sketch.unknown_mask);
    out.footprint = interior_free.clone();
  } else {
    if (cv::countNonZero(walls) == 0) {
      throw PriorMapError(name +
                          ": no traversable region: the drawing has no walls (all white), so "
                          "there is no inside to explore");
    }
    // Seal gaps in the outer wall by a morphological closing of the walls. Sealing the last gap
    // makes the enclosed area jump (before, the outside floods the building through the gap);
    // larger radii only fill notches of the outside. So take the smallest radius whose enclosed
    // area is at least half the largest, and go on only while the area still jumps (a second
    // part of the building with its own gap).
    // The page is padded so that closing never seals against the image border.
    const int max_radius =
        std::max(0, static_cast<int>(std::ceil(0.5 * config.max_outer_gap_m / m_per_px)));
    const int pad = max_radius + 2;
    cv::Mat1b padded_walls;
    cv::copyMakeBorder(walls, padded_walls, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar(0));
    const cv::Rect page(pad, pad, walls.cols, walls.rows);
    cv::Mat1f dist_to_wall;
    cv::distanceTransform(~padded_walls, dist_to_wall, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    std::vector<int> radii{0};
    for (double r = 1.0; r < max_radius; r = std::max(r + 1.0, r * 1.35))
      radii.push_back(static_cast<int>(r));
    if (max_radius > 0) radii.push_back(max_radius);
    std::vector<double> area(radii.size());
    std::vector<cv::Mat1b> footprints(radii.size());
    for (size_t i = 0; i < radii.size(); ++i) {
      footprints[i] = ~exteriorOf(closeWalls(padded_walls, dist_to_wall, radii[i]))(page);
      area[i] = cv::countNonZero(footprints[i] & ~walls);
    }
    const double best = *std::max_element(area.begin(), area.end());
    // A partial sketch (walls of whole regions left out) has an open outline: nothing, or only a
    // few closets, is enclosed. What the strokes span is then the best guess of the inside: the
    // convex hull of the ink. It is the fallback when the enclosed area leaves no region, too.
    std::vector<cv::Point> ink;
    cv::findNonZero(walls, ink);
    cv::Mat1b hull_footprint = cv::Mat1b::zeros(walls.size());
    if (ink.size() >= 3) {
      std::vector<cv::Point> hull;
      cv::convexHull(ink, hull);
      cv::fillConvexPoly(hull_footprint, hull, cv::Scalar(255));
    }
    size_t chosen = 0;
    if (best > 0.0) {
      while (area[chosen] < 0.5 * best) ++chosen;
      while (chosen + 1 < radii.size() && area[chosen + 1] > 1.25 * area[chosen]) ++chosen;
    }
    // The span of what is enclosed, without what the closing itself filled in (it rounds every
    // corner of the strokes, enclosed or not) nor the insides of loose loops. The chosen radius'
    // closing is done again rather than every radius' kept from the loop above: one closing against
    // a page-sized mask each.
    const cv::Mat1b loose_loops = looseLoopInteriors(walls);
    const auto diagonal = [](const cv::Rect& r) { return std::hypot(r.width, r.height); };
    const bool closet_only =
        best > 0.0 &&
        diagonal(enclosedSpan(footprints[chosen] &
                                  ~closeWalls(padded_walls, dist_to_wall, radii[chosen])(page) &
                                  ~loose_loops,
                              config.min_region_area_m2 / (m_per_px * m_per_px))) <
            config.min_enclosed_span_fraction * diagonal(cv::boundingRect(ink));
    if (best <= 0.0 || closet_only) {
      if (cv::countNonZero(hull_footprint & ~walls) == 0) {
        throw PriorMapError(name +
                            ": no traversable region: no area enclosed by walls (outer wall gaps "
                            "wider than max_outer_gap_m = " +
                            std::to_string(config.max_outer_gap_m) + " m at the scale guess?)");
      }
      // The hull alone spans the empty page between a drawing's arms (the Pittsburgh mine's
      // partial drawing: 555 guidepoints, 410 still unexplored at 409 s, most of them in rock).
      // Strokes nearer each other than open_outline_gap_m bound one place; what they close is the
      // inside. One triangulation point per half metre of ink is plenty at that scale.
      out.footprint = hull_footprint;
      if (config.open_outline_gap_m > 0.0) {
        constexpr double kPointSpacingM = 0.5;
        const cv::Mat1b near_strokes =
            ~exteriorOf(walls |
                        shortTriangles(walls, config.open_outline_gap_m / m_per_px,
                                       std::max(1, static_cast<int>(kPointSpacingM / m_per_px)))) &
            hull_footprint;
        if (cv::countNonZero(near_strokes & ~walls) > 0) out.footprint = near_strokes;
      }
      out.outer_outline_open = true;
    } else {
      out.outer_gap_closing_px = radii[chosen];
      out.footprint = footprints[chosen];
      fallback_footprint = hull_footprint;
    }
    interior_free = out.footprint & ~walls;
    if (config.drop_island_interiors) {
      // The hull's edge runs through the pillars at the rim of an open drawing, and
      // islandInteriors() takes their strokes for the outline's: loose loops are solid there too.
      // A closed outline keeps them: a loop beside it, not in it, is a second building.
      cv::Mat1b solid = islandInteriors(walls, ~out.footprint, interior_free);
      if (out.outer_outline_open) solid |= loose_loops;
      interior_free &= ~solid;
    }
  }
  return regionWithClearance(name, m_per_px, config, std::move(out), walls, interior_free,
                             fallback_footprint);
}

}  // namespace efs::prior_map
