// SPDX-License-Identifier: Zlib
// The exact texel bake (docs/design.md "Exact texels"): every texel square is clipped against every UV
// triangle that overlaps it (Sutherland-Hodgman against the triangle's three half-planes, in
// double), and the pieces are kept so that PT and VAT can be re-evaluated from moved vertices.
#include "hydrotex/bake/SurfaceBake.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "mass/MassMoments.hpp"
#include "bake/TexelClipping.hpp"

namespace hydrotex {

Status BakeSettings::validate() const {
  if (width < 16 || width > 4096)
    return Error{"bake width " + std::to_string(width) + " is outside 16..4096"};
  if (height < 16 || height > 4096)
    return Error{"bake height " + std::to_string(height) + " is outside 16..4096"};
  if (tileSize < 1 || tileSize > 256)
    return Error{"bake tile size " + std::to_string(tileSize) + " is outside 1..256"};
  return Ok{};
}

namespace {

// UVs may stray this far outside [0,1] (rounding in atlas generators); what lies outside is cut.
constexpr double kUvSlack = 1e-6;

// Texel the piece lands in (its key in tile order) and the piece itself.
struct KeyedPiece {
  std::uint32_t key;
  TexelPiece piece;
};

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

Expected<SurfaceBake> bakeSurface(const Mesh& mesh, const UvLayout& layout, const BakeSettings& settings) {
  if (Status valid = settings.validate(); !valid) return valid.error();
  const std::string& name = mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName;
  const std::size_t triangleCount = mesh.triangles.size();
  if (triangleCount == 0) return Error{name + ": no triangles to bake"};
  if (!layout.coversTriangles(triangleCount))
    return Error{name + ": UV layout has " + std::to_string(layout.uvTriangles.size()) +
                 " UV triangles for " + std::to_string(triangleCount) + " triangles"};
  if (triangleCount > 0xFFFFFFFFull) return Error{name + ": too many triangles to bake"};
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    if (!finite(mesh.positions[i])) return Error{name + ": vertex " + std::to_string(i) + " is not finite"};
  for (std::size_t i = 0; i < layout.uvs.size(); ++i) {
    const Eigen::Vector2d& uv = layout.uvs[i];
    if (!uv.allFinite()) return Error{name + ": UV " + std::to_string(i) + " is not finite"};
    if (uv.x() < -kUvSlack || uv.x() > 1.0 + kUvSlack || uv.y() < -kUvSlack || uv.y() > 1.0 + kUvSlack)
      return Error{name + ": UV " + std::to_string(i) + " (" + std::to_string(uv.x()) + ", " +
                   std::to_string(uv.y()) + ") lies outside [0,1]^2"};
  }

  // Scale for "zero" 3D area: rounding on a mesh of this size.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (const auto& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double zeroArea3d = 1e-14 * (mesh.positions.empty() ? 0.0 : (hi - lo).squaredNorm());

  const int width = settings.width, height = settings.height, tile = settings.tileSize;
  SurfaceBake bake;
  bake.width = width;
  bake.height = height;
  bake.tileSize = tile;
  const int tilesX = bake.tilesX(), tilesY = bake.tilesY();
  const std::uint32_t tileTexels = static_cast<std::uint32_t>(tile) * static_cast<std::uint32_t>(tile);
  auto keyOf = [&](int column, int row) {
    const std::uint32_t tileIndex = static_cast<std::uint32_t>((row / tile) * tilesX + column / tile);
    return tileIndex * tileTexels + static_cast<std::uint32_t>((row % tile) * tile + column % tile);
  };

  std::vector<KeyedPiece> keyed;
  keyed.reserve(triangleCount * 4);
  const int vertexCount = static_cast<int>(mesh.positions.size());
  const int uvCount = static_cast<int>(layout.uvs.size());

  for (std::size_t t = 0; t < triangleCount; ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    const Eigen::Vector3i& uvTri = layout.uvTriangles[t];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= vertexCount)
        return Error{name + ": triangle " + std::to_string(t) + " has vertex index " + std::to_string(tri[k]) +
                     " out of range"};
      if (uvTri[k] < 0 || uvTri[k] >= uvCount)
        return Error{name + ": UV triangle " + std::to_string(t) + " has UV index " + std::to_string(uvTri[k]) +
                     " out of range"};
    }
    // Texel coordinates: x = u * width, y = (1 - v) * height, so that texel (column, row) is
    // [column, column+1] x [row, row+1] (row 0 is v = 1, Mesh.hpp).
    std::array<double, 3> px{}, py{};
    for (int k = 0; k < 3; ++k) {
      px[k] = layout.uvs[uvTri[k]].x() * width;
      py[k] = (1.0 - layout.uvs[uvTri[k]].y()) * height;
    }
    const double twiceSigned = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]);
    const double uvArea = 0.5 * std::abs(twiceSigned);
    const Eigen::Vector3d& p0 = mesh.positions[tri[0]];
    const double area3d = 0.5 * (mesh.positions[tri[1]] - p0).cross(mesh.positions[tri[2]] - p0).norm();
    if (!(uvArea > 1e-14)) {
      if (area3d > zeroArea3d)
        return Error{name + ": triangle " + std::to_string(t) + " has zero UV area but 3D area " +
                     std::to_string(area3d) + " m^2"};
      continue;  // degenerate in 3D too: it carries nothing
    }
    // Edge functions, oriented so that the inside is positive whatever the UV winding.
    const std::array<detail::HalfPlane, 3> planes = detail::triangleHalfPlanes(px, py, twiceSigned);
    // Barycentric coordinates of a point (affine in x, y): b1 = (d2 x ...) solved once here.
    const double inverseTwice = 1.0 / twiceSigned;
    auto bary = [&](double x, double y, double& b1, double& b2) {
      b1 = ((x - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (y - py[0])) * inverseTwice;
      b2 = ((px[1] - px[0]) * (y - py[0]) - (x - px[0]) * (py[1] - py[0])) * inverseTwice;
    };
    const double minPieceArea = 1e-12 * std::min(uvArea, 1.0);

    const double minX = std::min({px[0], px[1], px[2]}), maxX = std::max({px[0], px[1], px[2]});
    const double minY = std::min({py[0], py[1], py[2]}), maxY = std::max({py[0], py[1], py[2]});
    const int column0 = std::max(0, static_cast<int>(std::floor(minX)));
    const int column1 = std::min(width - 1, static_cast<int>(std::floor(maxX)));
    const int row0 = std::max(0, static_cast<int>(std::floor(minY)));
    const int row1 = std::min(height - 1, static_cast<int>(std::floor(maxY)));
    const auto triangleIndex = static_cast<std::uint32_t>(t);

    for (int row = row0; row <= row1; ++row) {
      const double y0 = row, y1 = row + 1.0;
      for (int column = column0; column <= column1; ++column) {
        const double x0 = column, x1 = column + 1.0;
        // Corner tests: outside one half-plane entirely -> nothing; inside all -> the whole texel.
        bool outside = false, whole = true;
        std::array<bool, 3> cuts{};
        for (int k = 0; k < 3; ++k) {
          const double e00 = planes[k].at(x0, y0), e10 = planes[k].at(x1, y0);
          const double e01 = planes[k].at(x0, y1), e11 = planes[k].at(x1, y1);
          const double emin = std::min(std::min(e00, e10), std::min(e01, e11));
          const double emax = std::max(std::max(e00, e10), std::max(e01, e11));
          if (emax <= 0.0) { outside = true; break; }
          cuts[k] = emin < 0.0;
          whole = whole && !cuts[k];
        }
        if (outside) continue;
        TexelPiece piece;
        piece.triangle = triangleIndex;
        double pieceArea = 1.0, cx = column + 0.5, cy = row + 0.5;
        if (!whole) {
          detail::Polygon a = detail::texelSquare(column, row), b;
          detail::Polygon* current = &a;
          detail::Polygon* next = &b;
          for (int k = 0; k < 3 && current->count > 0; ++k) {
            if (!cuts[k]) continue;
            detail::clipAgainst(*current, planes[k], *next);
            std::swap(current, next);
          }
          // Shoelace area and centroid, relative to the texel corner to keep the digits.
          double twice = 0.0, sx = 0.0, sy = 0.0;
          for (int i = 0; i < current->count; ++i) {
            const int j = (i + 1 == current->count) ? 0 : i + 1;
            const double xi = current->x[i] - x0, yi = current->y[i] - y0;
            const double xj = current->x[j] - x0, yj = current->y[j] - y0;
            const double cross = xi * yj - xj * yi;
            twice += cross;
            sx += (xi + xj) * cross;
            sy += (yi + yj) * cross;
          }
          pieceArea = 0.5 * std::abs(twice);
          if (!(pieceArea > minPieceArea)) continue;
          cx = x0 + sx / (3.0 * twice);
          cy = y0 + sy / (3.0 * twice);
        }
        double b1 = 0.0, b2 = 0.0;
        bary(cx, cy, b1, b2);
        piece.areaFraction = static_cast<float>(pieceArea / uvArea);
        piece.centroidBary1 = static_cast<float>(b1);
        piece.centroidBary2 = static_cast<float>(b2);
        keyed.push_back({keyOf(column, row), piece});
      }
    }
  }

  // Counting sort by tile-order key; stable, so pieces stay in triangle order within a texel.
  const std::size_t keyCount = static_cast<std::size_t>(tilesX) * static_cast<std::size_t>(tilesY) * tileTexels;
  std::vector<std::uint32_t> firstOfKey(keyCount + 1, 0);
  for (const KeyedPiece& k : keyed) ++firstOfKey[k.key + 1];
  std::size_t covered = 0;
  for (std::size_t k = 0; k < keyCount; ++k) covered += firstOfKey[k + 1] != 0 ? 1 : 0;
  bake.texelIndex.reserve(covered);
  bake.pieceStart.reserve(covered + 1);
  bake.tileStart.assign(static_cast<std::size_t>(tilesX) * tilesY + 1, 0);
  std::uint32_t running = 0;
  for (std::size_t k = 0; k < keyCount; ++k) {
    const std::uint32_t count = firstOfKey[k + 1];
    firstOfKey[k] = running;
    if (count == 0) continue;
    const std::size_t tileIndex = k / tileTexels, local = k % tileTexels;
    const std::size_t row = (tileIndex / tilesX) * tile + local / tile;
    const std::size_t column = (tileIndex % tilesX) * tile + local % tile;
    bake.tileStart[tileIndex + 1] = static_cast<std::uint32_t>(bake.texelIndex.size() + 1);
    bake.texelIndex.push_back(static_cast<std::uint32_t>(row * width + column));
    bake.pieceStart.push_back(running);
    running += count;
  }
  bake.pieceStart.push_back(running);
  // tileStart[t + 1] holds "last covered + 1" of tile t, or 0 for an empty tile: fill forward.
  for (std::size_t t = 1; t < bake.tileStart.size(); ++t)
    bake.tileStart[t] = std::max(bake.tileStart[t], bake.tileStart[t - 1]);
  bake.pieces.resize(keyed.size());
  for (const KeyedPiece& k : keyed) bake.pieces[firstOfKey[k.key]++] = k.piece;
  return bake;
}

SurfaceTextures evaluateSurface(const SurfaceBake& bake, const Mesh& mesh, const UvLayout& layout) {
  // Per triangle, once: area vector (geometric normal times area: exact VAT) and the affine map's
  // derivatives d position / du and d position / dv.
  const std::size_t triangleCount = mesh.triangles.size();
  struct TriangleFrame {
    Eigen::Vector3d p0 = Eigen::Vector3d::Zero(), p1 = p0, p2 = p0, areaVector = p0, dPdu = p0, dPdv = p0;
    double area = 0.0, uvArea = 0.0;
  };
  std::vector<TriangleFrame> frames(triangleCount);
  const bool haveUv = layout.uvTriangles.size() == triangleCount;
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    TriangleFrame& f = frames[t];
    const int vertexCount = static_cast<int>(mesh.positions.size());
    if ((tri.array() < 0).any() || (tri.array() >= vertexCount).any()) continue;  // carries nothing
    f.p0 = mesh.positions[tri[0]];
    f.p1 = mesh.positions[tri[1]];
    f.p2 = mesh.positions[tri[2]];
    const Eigen::Vector3d e1 = f.p1 - f.p0, e2 = f.p2 - f.p0;
    f.areaVector = 0.5 * e1.cross(e2);
    f.area = f.areaVector.norm();
    if (!haveUv) continue;
    const Eigen::Vector3i& uvTri = layout.uvTriangles[t];
    const int uvCount = static_cast<int>(layout.uvs.size());
    if ((uvTri.array() < 0).any() || (uvTri.array() >= uvCount).any()) continue;
    const Eigen::Vector2d d1 = layout.uvs[uvTri[1]] - layout.uvs[uvTri[0]];
    const Eigen::Vector2d d2 = layout.uvs[uvTri[2]] - layout.uvs[uvTri[0]];
    const double det = d1.x() * d2.y() - d2.x() * d1.y();
    f.uvArea = 0.5 * std::abs(det);
    if (det == 0.0) continue;
    // e = dPdu du + dPdv dv for both edges: invert the 2x2 UV edge matrix.
    f.dPdu = (e1 * d2.y() - e2 * d1.y()) / det;
    f.dPdv = (e2 * d1.x() - e1 * d2.x()) / det;
  }

  // Lids over openings (an open hull): per triangle, whether it is one.
  std::vector<char> opening;
  OpeningMoments lids;
  if (mesh.hasOpenings()) {
    opening.assign(triangleCount, 0);
    for (std::uint32_t t : mesh.openingTriangles) {
      if (t >= triangleCount || opening[t]) continue;
      opening[t] = 1;
      // A triangle's area moments about the origin: a s / 3 and a q / 12 (MassMoments.hpp).
      const TriangleFrame& f = frames[t];
      double s[3], q[6];
      detail::triangleCornerSums(f.p0.data(), f.p1.data(), f.p2.data(), s, q);
      lids.area += f.area;
      lids.first += f.area / 3.0 * Eigen::Vector3d(s[0], s[1], s[2]);
      Eigen::Matrix3d second;
      second << q[0], q[3], q[4], q[3], q[1], q[5], q[4], q[5], q[2];
      lids.second += f.area / 12.0 * second;
    }
  }

  SurfaceTextures out;
  out.width = bake.width;
  out.height = bake.height;
  const std::size_t covered = bake.coveredCount();
  out.position.resize(covered);
  out.areaVector.resize(covered);
  out.area.resize(covered);
  out.edgeU.resize(covered);
  out.edgeV.resize(covered);
  if (!opening.empty()) {
    out.openingArea.assign(covered, 0.0f);
    out.openingAreaVector.assign(covered, Eigen::Vector3f::Zero());
    out.openingPosition.assign(covered, Eigen::Vector3f::Zero());
  }
  out.openings = lids;
  const double texelU = bake.width > 0 ? 1.0 / bake.width : 0.0;
  const double texelV = bake.height > 0 ? 1.0 / bake.height : 0.0;

  std::vector<Eigen::Vector3d> centroids;  // the current texel's pieces' (momentReach)
  for (std::size_t i = 0; i < covered; ++i) {
    Eigen::Vector3d areaVector = Eigen::Vector3d::Zero(), weightedCentroid = Eigen::Vector3d::Zero();
    Eigen::Vector3d edgeU = Eigen::Vector3d::Zero(), edgeV = Eigen::Vector3d::Zero();
    double area = 0.0, uvWeight = 0.0, flux = 0.0;  // flux: sum of centroid . piece area vector
    double openingArea = 0.0;
    Eigen::Vector3d openingAreaVector = Eigen::Vector3d::Zero(), openingWeighted = Eigen::Vector3d::Zero();
    Eigen::Matrix3d firstMoment = Eigen::Matrix3d::Zero();  // Sum c_k A_k^T over the pieces
    centroids.clear();
    for (std::uint32_t k = bake.pieceStart[i]; k < bake.pieceStart[i + 1]; ++k) {
      const TexelPiece& piece = bake.pieces[k];
      if (piece.triangle >= triangleCount) continue;  // a bake of another mesh: skip, never crash
      const TriangleFrame& f = frames[piece.triangle];
      const double fraction = piece.areaFraction;
      const double b1 = piece.centroidBary1, b2 = piece.centroidBary2;
      const Eigen::Vector3d centroid = (1.0 - b1 - b2) * f.p0 + b1 * f.p1 + b2 * f.p2;
      const Eigen::Vector3d pieceAreaVector = fraction * f.areaVector;
      const double pieceArea = fraction * f.area;
      areaVector += pieceAreaVector;
      area += pieceArea;
      if (!opening.empty() && opening[piece.triangle]) {
        openingArea += pieceArea;
        openingAreaVector += pieceAreaVector;
        openingWeighted += pieceArea * centroid;
      }
      weightedCentroid += pieceArea * centroid;
      flux += centroid.dot(pieceAreaVector);
      firstMoment += centroid * pieceAreaVector.transpose();
      centroids.push_back(centroid);
      const double pieceUv = fraction * f.uvArea;
      uvWeight += pieceUv;
      edgeU += pieceUv * f.dPdu;
      edgeV += pieceUv * f.dPdv;
    }
    Eigen::Vector3d position = area > 0.0 ? Eigen::Vector3d(weightedCentroid / area) : Eigen::Vector3d::Zero();
    // Shift along the area vector so that position . areaVector == flux (then sum p.A / 3 is the
    // exact enclosed volume). The shift is (flux - c.A) / |A|, second order in the texel size on a
    // smooth surface. Where pieces nearly cancel (a texel straddling opposite-facing charts) the
    // shift would blow up, so it is left out there: that texel's volume share is then first order.
    const double areaVectorSquared = areaVector.squaredNorm();
    if (areaVectorSquared > 1e-2 * area * area && areaVectorSquared > 0.0)
      position += areaVector * ((flux - position.dot(areaVector)) / areaVectorSquared);
    out.position[i] = position.cast<float>();
    out.areaVector[i] = areaVector.cast<float>();
    out.area[i] = static_cast<float>(area);
    if (bake.pieceStart[i + 1] - bake.pieceStart[i] > 1) {
      // What the one stored position leaves out of the pieces' first moment, against the stored
      // (float) p and A, so that the texels' sums plus these are the pieces' own.
      out.momentTexel.push_back(static_cast<std::uint32_t>(i));
      const Eigen::Matrix3d stored = out.position[i].cast<double>() * out.areaVector[i].cast<double>().transpose();
      out.momentCorrection.push_back((firstMoment - stored).cast<float>());
      double reach = 0.0;
      for (const Eigen::Vector3d& centroid : centroids)
        reach = std::max(reach, (centroid - out.position[i].cast<double>()).norm());
      out.momentReach.push_back(static_cast<float>(reach));
    }
    if (!opening.empty()) {
      out.openingArea[i] = static_cast<float>(openingArea);
      out.openingAreaVector[i] = openingAreaVector.cast<float>();
      out.openingPosition[i] = openingArea > 0.0 ? Eigen::Vector3d(openingWeighted / openingArea).cast<float>() : out.position[i];
    }
    if (uvWeight > 0.0) {
      out.edgeU[i] = (edgeU * (texelU / uvWeight)).cast<float>();
      out.edgeV[i] = (edgeV * (texelV / uvWeight)).cast<float>();
    } else {
      out.edgeU[i].setZero();
      out.edgeV[i].setZero();
    }
  }
  return out;
}

}  // namespace hydrotex
