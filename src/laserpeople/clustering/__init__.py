"""Clustering of 2D points: single linkage with a distance threshold (000 Sec. 4.1) and
mean shift with a flat kernel (004 Sec. 2)."""

from laserpeople.clustering.mean_shift import MeanShiftResult, cluster_covariances, mean_shift
from laserpeople.clustering.single_linkage import SingleLinkageParams, single_linkage

__all__ = [
    "MeanShiftResult",
    "SingleLinkageParams",
    "cluster_covariances",
    "mean_shift",
    "single_linkage",
]
