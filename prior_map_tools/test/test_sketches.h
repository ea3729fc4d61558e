// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Hand-drawn-like synthetic sketches for the prior_map_tools tests. Coordinates are pixels.
#pragma once

#include <opencv2/imgproc.hpp>

namespace efs::prior_map::test {

/// A 300 x 200 px building on a 400 x 300 px page: an east-west corridor (rows 90-110) with three
/// rooms north and two south, each with a door, and a 12-px door in the WEST OUTER wall.
/// Walls are 2 px black lines on white.
inline cv::Mat1b drawBuilding() {
  cv::Mat1b img(300, 400, uint8_t(255));
  const cv::Scalar black(0);
  const int x0 = 50, x1 = 350, y0 = 50, y1 = 250;
  // Outer wall with a gap (door to the outside) on the west side at rows 94..106.
  cv::line(img, {x0, y0}, {x1, y0}, black, 2);
  cv::line(img, {x0, y1}, {x1, y1}, black, 2);
  cv::line(img, {x1, y0}, {x1, y1}, black, 2);
  cv::line(img, {x0, y0}, {x0, 94}, black, 2);
  cv::line(img, {x0, 106}, {x0, y1}, black, 2);
  // Corridor walls (rows 130 and 170) with a 12-px door into each room.
  for (int wall_y : {130, 170}) {
    int from = x0;
    const int rooms = wall_y == 130 ? 3 : 2;
    const int w = (x1 - x0) / rooms;
    for (int r = 0; r < rooms; ++r) {
      const int door = x0 + r * w + w / 2;
      cv::line(img, {from, wall_y}, {door - 6, wall_y}, black, 2);
      from = door + 6;
    }
    cv::line(img, {from, wall_y}, {x1, wall_y}, black, 2);
    for (int r = 1; r < rooms; ++r) {
      const int x = x0 + r * w;
      cv::line(img, {x, wall_y == 130 ? y0 : 170}, {x, wall_y == 130 ? 130 : y1}, black, 2);
    }
  }
  return img;
}

/// Pixel inside the corridor and inside the first north room, and a pixel outside.
inline cv::Point corridorPixel() { return {200, 150}; }
inline cv::Point northRoomPixel() { return {100, 90}; }
inline cv::Point southRoomPixel() { return {300, 210}; }
inline cv::Point outsidePixel() { return {20, 150}; }

/// A plus-shaped corridor, 20 px wide, arms 120 px long, on a 300 x 300 px page.
inline cv::Mat1b drawPlus() {
  cv::Mat1b img(300, 300, uint8_t(255));
  cv::Mat1b inside = cv::Mat1b::zeros(img.size());
  cv::rectangle(inside, cv::Rect(30, 140, 240, 20), cv::Scalar(255), cv::FILLED);
  cv::rectangle(inside, cv::Rect(140, 30, 20, 240), cv::Scalar(255), cv::FILLED);
  cv::Mat1b edge;
  cv::dilate(inside, edge, cv::getStructuringElement(cv::MORPH_RECT, {5, 5}));
  img.setTo(0, edge & ~inside);
  return img;
}

}  // namespace efs::prior_map::test
