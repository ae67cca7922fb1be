"""Clustering of foreground points (004 Sec. 2): mean shift with a flat kernel."""

from laserpeople.clustering.mean_shift import MeanShiftResult, cluster_covariances, mean_shift

__all__ = ["MeanShiftResult", "cluster_covariances", "mean_shift"]
