// The results file of `ricochet dem drop --out FILE.csv`: one CSV row per drop, the sphere tracks
// beside it (FILE.tracks.csv) and the bed's angle of repose (FILE.repose.json). Rows are appended
// as each drop ends, so that a killed study resumes with the drops it has not run yet.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "drop.hpp"

namespace ricochet::dem {

/// One drop as stored: the cells of drop_row_names() by name (SI units in the names).
struct DropRow {
  std::map<std::string, std::string> cells;
  double number(const std::string& name) const;  ///< NaN when missing or not a number
  std::string text(const std::string& name) const;
};

/// The columns of a drop row, in file order (id, seed, h_drop_m, status, depths [m], speeds
/// [m/s], Katsuragi-Durian fits, cost, bed_key, message).
const std::vector<std::string>& drop_row_names();

/// `result` of replica `seed` (-1: the decks' own seeds) as a row.
DropRow drop_row(const DropResult& result, long seed);

class DropStore {
 public:
  /// `csv_path` ends in .csv (the caller checks the option).
  explicit DropStore(std::string csv_path);

  const std::string& path() const { return path_; }
  std::string tracks_path() const;  ///< FILE.tracks.csv
  std::string repose_path() const;  ///< FILE.repose.json

  /// Ids of the drops already in the file (none when it does not exist).
  std::set<std::string> done_ids() const;
  /// Appends the row and the track of one drop. Throws InputError naming the file (--out) when
  /// it cannot be written.
  void append(const DropResult& result, long seed) const;
  /// Every stored drop, in file order; InputError with file and line on a malformed row.
  std::vector<DropRow> rows() const;
  /// The stored tracks by drop id.
  std::map<std::string, DropTrack> tracks() const;

 private:
  std::string path_;
};

/// FNV-1a 64 of the drop and repose decks' text (16 hex digits): the provenance of a study.
std::string drop_decks_digest(const Decks& decks);

}  // namespace ricochet::dem
