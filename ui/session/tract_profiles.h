// SPDX-License-Identifier: GPL-3.0-or-later
// Tract profiles from files, as `dtfabric profile` and the Python module's dtfabric.profile() run them: the
// tract files (each file, or each of its groups, a bundle), the scalar images (fa/md/ad/rd of a tensor or a
// DWI fitted on the fly, or any image as NAME=IMAGE), the start region; the engine is
// surfaces/analyses/tract_profile.h. Out: one profile per bundle, and the tidy table, JSON and figure made
// from them.
#pragma once

#include "render/profile_plot.h"
#include "surfaces/analyses/tract_profile.h"
#include "ui/session/tensor_input.h"

#include <string>
#include <vector>

namespace dtf::session {

// One --scalar: a built-in map of the tensor (fa, md, ad, rd) or NAME=IMAGE.
struct ScalarSpec {
  std::string name;  // written verbatim in the table
  std::string image; // empty for a built-in map
};
// Throws InputError naming the spec for an empty name or image, a name with a tab or line break, or a bare
// word that is not fa, md, ad or rd.
ScalarSpec parseScalarSpec(const std::string& text);
// The image of a NAME=IMAGE scalar: one component, some voxels; InputError naming the file otherwise.
ScalarVolume readScalarImage(const ScalarSpec& spec);

struct ProfileRequest {
  std::vector<std::string> tracts;
  std::string groups; // "": each file is one bundle; "all": each group of each file; "A,B": those groups
  std::vector<std::string> scalars; // ScalarSpec texts
  std::string tensor;               // the tensor file or DWI of fa/md/ad/rd
  std::string layout = "auto";      // its tensor layout
  TensorInputOptions tensorOptions; // a DWI's gradients and fit mask
  std::string start;                // X,Y,Z or a region SPEC the streamlines start near ("" none)
  surfaces::ProfileOptions options;
};

struct ProfiledBundle {
  std::string name;  // the file's stem or the group's name (qualified when two bundles would share one)
  std::string file;  // the tract file
  std::string group; // the group, or empty
  std::string axis;  // where the core starts and ends, e.g. "inferior → superior"
  surfaces::BundleProfile profile;
};

struct ProfileResult {
  std::vector<std::string> scalars; // names, in the order asked
  std::vector<ProfiledBundle> bundles;
  surfaces::ProfileOptions options;
  std::string start; // the start region as given ("" none)
};

// Every file a request reads (tracts, tensor, gradients, mask, images, a start image): outputs must not
// replace them.
std::vector<std::string> profileInputs(const ProfileRequest& request);

// The world RAS mm point a --start SPEC names: X,Y,Z itself, or the centre of a region as
// ui/session/region_spec.h reads it (a sphere's or box's centre, the mean of a mask's voxels). Throws
// InputError naming the spec for a malformed one or an unreadable image.
glm::dvec3 startPointOf(const std::string& spec);

// Reads everything and profiles every bundle. Throws InputError naming the file (an unreadable or empty
// bundle, a missing group, an unreadable or multi-volume image, a tensor that is not one) and UsageError for
// bad combinations (fa without --tensor, a scalar named twice).
ProfileResult runProfile(const ProfileRequest& request);

// The tidy table: a header line `bundle scalar node x y z mean sd ci_low ci_high streamlines`, then one row
// per bundle, scalar and node (tab-separated; NaN where there is no value).
std::string profileTable(const ProfileResult& result);
// The same rows as JSON, with the bundles' facts and the options ({"bundles": [...], "rows": [...], ...}).
std::string profileJson(const ProfileResult& result);
// The figure of the result: a panel per scalar, a line and band per bundle, the node axis labelled with the
// bundles' common direction (each bundle's own in its legend entry when they differ).
render::ProfileFigure profileFigure(const ProfileResult& result);

} // namespace dtf::session
