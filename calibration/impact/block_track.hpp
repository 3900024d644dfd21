// The time series of one resolved impact: the block's state and the contact force on it, record
// by record, as a LIGGGHTS campaign keeps it next to its impact set (docs/impact-sets.md,
// "Tracks"). The one type and the one HDF5 reader and writer of /dem/tracks/ID: `ricochet stats`
// summarises tracks, the report plots them, and the resolved model's driver (src-ext) writes them
// through write_block_track.
//
// Layout: dataset /dem/tracks/ID (ID = the impact's id), n x k doubles, one row per record; its
// string attribute `columns` names the k columns with their units ("t[s],x[m],...") in any order
// and any subset of BlockTrack::column_names(); the optional attribute `block_mass_kg` is the
// mass of the simulated block whose force the track records; `frame` says the frame in words.
// Frame: the paper's (x flight direction, y up, omega and torque > 0 counter-clockwise).
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace ricochet {

/// One impact's records, SI units, every column as long as t. A column the file does not have
/// (tracks written before the torque and overlap columns existed) is NaN throughout.
struct BlockTrack {
  std::vector<double> t;            ///< time [s]
  std::vector<double> x, y;         ///< centre of mass [m]
  std::vector<double> theta;        ///< orientation [rad], continuous (unwrapped)
  std::vector<double> vx, vy;       ///< velocity of the centre of mass [m/s]
  std::vector<double> w;            ///< spin [rad/s]
  std::vector<double> fcx, fcy;     ///< contact force on the simulated block [N]
  std::vector<double> penetration;  ///< depth of the block's lowest point below the surface [m]
  std::vector<double> ke_block;     ///< the block's kinetic energy [J]
  std::vector<double> ke_grains;    ///< the grains' kinetic energy [J]
  /// Contact torque on the simulated block about its centre of mass [N*m] (like fcx, fcy).
  std::vector<double> torque;
  /// Largest overlap over diameter of the grain contacts at that record (grain-grain and
  /// grain-block pairs; d the smaller sphere's diameter) [-].
  std::vector<double> overlap_d_max;
  /// Standard errors of fcx, fcy [N] and torque [N*m] when the force is estimated rather than
  /// recorded (from tracked accelerations, kinematics/track_forces.hpp); NaN when not given.
  std::vector<double> sigma_fcx, sigma_fcy, sigma_torque;
  /// Mass of the simulated block [kg] (a slab of width w carries w / L of the lab block); NaN
  /// when the file does not say.
  double block_mass_kg = std::numeric_limits<double>::quiet_NaN();

  /// The seventeen columns with their SI units, in the order the writer stores them:
  /// "t[s]", "x[m]", "y[m]", "theta[rad]", "vx[m/s]", "vy[m/s]", "w[rad/s]", "fcx[N]", "fcy[N]",
  /// "penetration[m]", "ke_block[J]", "ke_grains[J]", "torque[N*m]", "overlap_d_max[-]",
  /// "sigma_fcx[N]", "sigma_fcy[N]", "sigma_torque[N*m]".
  static const std::vector<std::string>& column_names();
  std::size_t size() const { return t.size(); }
  /// Column `name`, with or without its unit ("torque" or "torque[N*m]"); nullptr for an
  /// unknown name.
  std::vector<double>* column(const std::string& name);
  const std::vector<double>* column(const std::string& name) const;
  /// Row-major copy, size() x column_names().size(), in column_names() order (NaN where a
  /// column is shorter than t).
  std::vector<double> rows() const;
  /// The inverse of rows() for any subset and order of columns, given by name (`columns`, with
  /// or without units): missing columns are NaN, unknown ones are ignored, values are taken as
  /// stored. Throws std::invalid_argument when the data is not a whole number of rows or there
  /// is no t column.
  static BlockTrack from_rows(const std::vector<double>& rows,
                              const std::vector<std::string>& columns);
  /// Every column as long as t, NaN where it had none.
  void pad();
};

/// The group of the tracks in an HDF5 file.
inline constexpr const char* kTracksGroup = "/dem/tracks";

/// The ids of the tracks in `path`, in the file's (name) order; empty when `path` is not an
/// HDF5 file or has no /dem/tracks.
std::vector<std::string> block_track_ids(const std::string& path);

/// Reads /dem/tracks/ID of `path` by its `columns` attribute (without it, the first campaigns'
/// twelve columns t ... ke_grains). Throws InputError(path, 0, "/dem/tracks/ID", ...) when the
/// track is missing, not a 2-D table of as many columns as its attribute names, has no t
/// column, or stores a known column in another unit than its SI one.
BlockTrack read_block_track(const std::string& path, const std::string& id);

/// Writes (replacing) /dem/tracks/ID of `path` (created if missing; other objects kept): all
/// seventeen columns, their names, the frame, and block_mass_kg when it is finite. Throws
/// std::invalid_argument for an empty id, a track without records or a column longer than t.
void write_block_track(const std::string& path, const std::string& id, const BlockTrack& track);

}  // namespace ricochet
