# SPDX-License-Identifier: GPL-3.0-or-later
"""DIPY's tract profile of a bundle cut out of a tractogram, for the parity test of `dtfabric profile`.

    dipy_profile.py TRACTS.tck SCALAR.nii.gz X,Y,Z,R[;X,Y,Z,R...] BUNDLE_OUT.tck PROFILE_OUT.tsv

The bundle: the streamlines with a vertex within R mm of every sphere's centre (world RAS mm), in file order,
written to BUNDLE_OUT.tck. Its profile as pyAFQ computes one with DIPY: orient_by_streamline(bundle,
bundle[0]), then afq_profile over 100 nodes with weights=gaussian_weights ("dipy_gauss") and without weights
("dipy_mean"). "full_gauss" is the same profile weighted by the textbook Mahalanobis distance (the full
covariance; DIPY 1.6 inverts only its upper triangle), computed here from DIPY's resampling and sampling.
The first line says how many streamlines the bundle has and how many DIPY flipped.
"""
import sys

import nibabel as nib
import numpy as np
from dipy.stats.analysis import afq_profile, gaussian_weights
from dipy.tracking.streamline import (Streamlines, orient_by_streamline, set_number_of_points,
                                      values_from_volume)

NODES = 100


def main():
    tracts, scalar, spheres, bundle_out, profile_out = sys.argv[1:6]
    lines = nib.streamlines.load(tracts).streamlines
    image = nib.load(scalar)
    data, affine = image.get_fdata(), image.affine
    centres = [np.array([float(v) for v in s.split(",")]) for s in spheres.split(";")]
    keep = [s for s in lines
            if all(np.min(np.linalg.norm(s - c[:3], axis=1)) <= c[3] for c in centres)]
    if not keep:
        sys.exit("no streamline passes the spheres")
    bundle = Streamlines(keep)
    nib.streamlines.save(nib.streamlines.Tractogram(bundle, affine_to_rasmm=np.eye(4)), bundle_out)

    oriented = orient_by_streamline(bundle, bundle[0])
    flipped = sum(int(not np.array_equal(a[0], b[0])) for a, b in zip(bundle, oriented))
    gauss = afq_profile(data, oriented, affine, n_points=NODES, weights=gaussian_weights)
    mean = afq_profile(data, oriented, affine, n_points=NODES)

    nodes = np.asarray(set_number_of_points(oriented, NODES))  # (S, N, 3)
    values = np.asarray(values_from_volume(data, nodes, affine))  # (S, N)
    full = np.zeros(NODES)
    for k in range(NODES):
        p = nodes[:, k, :].astype(float)
        d = p - p.mean(0)
        c = np.cov(p.T, ddof=0)
        dist = np.sqrt(np.einsum("si,ij,sj->s", d, np.linalg.inv(c), d))
        w = (1 / dist) / np.sum(1 / dist)
        full[k] = np.sum(w * values[:, k])

    with open(profile_out, "w") as f:
        f.write("# streamlines %d flipped %d\n" % (len(bundle), flipped))
        f.write("node\tdipy_gauss\tdipy_mean\tfull_gauss\n")
        for k in range(NODES):
            f.write("%d\t%.9g\t%.9g\t%.9g\n" % (k, gauss[k], mean[k], full[k]))


if __name__ == "__main__":
    main()
