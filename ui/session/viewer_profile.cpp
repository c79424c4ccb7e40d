// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/viewer_profile.h"

#include "io/model/error.h"
#include "io/model/tensor_field.h"
#include "ui/session/tract_profiles.h"

namespace dtf::session {

std::vector<std::string> viewerProfileScalars(const ViewerDataset& data) {
  if (data.fibres && !data.pairedTensor)
    return data.fa.data.empty() ? std::vector<std::string>{} : std::vector<std::string>{"fa"};
  return {"fa", "md", "ad", "rd"};
}

ViewerProfileResult profileForViewer(const ViewerProfileJob& job) {
  ViewerProfileResult r;
  r.serial = job.serial;
  r.scalar = job.scalar;
  try {
    if (!job.lines || !job.data) throw InputError("no tracts or no data to profile");
    const ViewerDataset& data = *job.data;
    ScalarVolume map;
    std::string name = job.scalar;
    if (job.scalar.find('=') != std::string::npos) {
      // NAME=IMAGE: any scalar image, read as `dtfabric profile --scalar NAME=IMAGE` reads it.
      const ScalarSpec spec = parseScalarSpec(job.scalar);
      map = readScalarImage(spec);
      name = spec.name;
    } else if (data.fibres && !data.pairedTensor) {
      if (job.scalar != "fa" || data.fa.data.empty())
        throw InputError("a fibre set without a tensor has no " + job.scalar + " to profile");
      map = data.fa;
    } else {
      // As `dtfabric profile --scalar fa|md|ad|rd --tensor T` computes them.
      MetricMaps maps = computeMetricMaps(data.loaded.field, false, false);
      if (job.scalar == "fa")
        map = std::move(maps.fa);
      else if (job.scalar == "md")
        map = std::move(maps.md);
      else if (job.scalar == "ad")
        map = std::move(maps.ad);
      else if (job.scalar == "rd")
        map = std::move(maps.rd);
      else
        throw InputError("no scalar '" + job.scalar + "' to profile (fa, md, ad or rd)");
    }
    const std::vector<surfaces::ProfileScalar> scalars = {{name, &map}};
    r.profile = surfaces::profileBundle(*job.lines, job.which.get(), scalars, surfaces::ProfileOptions{});
    r.axis = surfaces::nodeAxisLabel(r.profile.core.front(), r.profile.core.back());
  } catch (const std::exception& e) {
    r.error = e.what();
    r.profile = {};
  }
  return r;
}

} // namespace dtf::session
