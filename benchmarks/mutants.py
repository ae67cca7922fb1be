"""Mutation run over the equations of 000 (group tracker), 002 (Cluster Sorting, colour
re-identification) and 004 (particle filters): do the tests fail when the code is wrong?

Each mutant is one exact snippet of a source file under ``src/laserpeople`` and its
replacement (a near miss of the paper's formula: a wrong weight, a dropped term, a swapped
probability). For each mutant the script copies ``src/``, ``tests/``,
``benchmarks/`` and ``pyproject.toml`` into a fresh temporary directory, patches the copy (never the
worktree), and runs the mutant's tests there with ``PYTHONPATH`` pointing at the copy and
without the real recordings (``LASERPEOPLE_SHARED_DATA`` unset and no ``../shared``
beside the copy, so tests that need them skip). A mutant is *killed* when the tests fail,
*survived* when they pass; *stale* when its snippet is not found exactly once (the code
changed: update the list). The tests of the unmutated copy are run first (``--no-baseline``
skips this): a mutant is only meaningful when they pass::

    PYTHONPATH=src .venv/bin/python benchmarks/mutants.py [--jobs 2] [--only NAME ...]
    PYTHONPATH=src .venv/bin/python benchmarks/mutants.py --list

``--list`` marks stale mutants (without running anything). Exit status 1 when a mutant
survives or is stale.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
TIMEOUT = 1800.0
"""Seconds a mutant's tests (or the baseline) may run; a mutant that makes them hang is
counted killed, with the time out named in the table."""


@dataclass(frozen=True)
class Mutant:
    """One near miss: ``original`` (exactly once in ``path``) becomes ``replacement``.

    Attributes:
        name: Short name (``--only``).
        paper: Paper and equation it breaks (e.g. "000 eq. 32").
        path: Source file relative to ``src/laserpeople`` (``../../benchmarks/...``: a
            benchmark script the tests import, patched in the copy as well).
        original: Exact snippet of the file.
        replacement: What it becomes.
        tests: Test files (or node ids) to run, relative to the repository.
    """

    name: str
    paper: str
    path: str
    original: str
    replacement: str
    tests: tuple[str, ...]


# the tests of issue 33 first: with -x a killed mutant stops at its first failure
GROUPS = (
    "tests/test_paper_groups.py",
    "tests/test_track_groups.py",
    "tests/test_track_groups_fast.py",
    "tests/test_track_groups_sim.py",
)
CSA = ("tests/test_paper_csa.py", "tests/test_track_csa.py")
PF = ("tests/test_paper_pf.py", "tests/test_pf_equations.py", "tests/test_pf_trackers.py")
REID = (
    "tests/test_paper_reid.py",
    "tests/test_identity_appearance.py",
    "tests/test_identity_reid.py",
)
FIT = ("tests/test_paper_fit.py", "tests/test_fit.py")
MEAN_SHIFT = ("tests/test_mean_shift.py",)
PEOPLE_GLUE = ("tests/test_track_people_glue.py",)

CSA_CONFIRM = ("tests/test_track_csa.py", "tests/test_paper_csa.py")
FEET_REFRESH = ("tests/test_pf_feet_refresh.py", "tests/test_pf_feet_cells.py")
KEPT = ("tests/test_pf_objects.py", "tests/test_pf_feet_shapes.py")
PROXEMIC = ("tests/test_groups_random_e2e.py",)
LISTING = (
    "tests/test_track_mht_core.py",
    "tests/test_track_mht_bounds.py",
    # with the C extension built, the listing tests run it; this one holds the Python
    # reference to it
    "tests/test_track_mht_compiled.py",
)
HISTOGRAM = (
    "tests/test_background_histogram.py",
    "tests/test_pipeline_static_people.py",
    "tests/test_background_histogram_compiled.py",
)
ROS1 = ("tests/test_io_ros1_reader.py",)
WALKED = ("tests/test_track_moving_robot.py",)
PERSON = ("tests/test_track_person_tracks.py",)
KALMAN = ("tests/test_track_kalman.py",)
KALMAN_ROWS = ("tests/test_track_kalman_compiled.py",)
DEFERRED = ("tests/test_detect_deferred.py",)
SPARSE = (
    "tests/test_detect_sparse.py",
    "tests/test_detect_block_compiled.py",  # (the Python reference against the extension)
)
FEATURES = (
    "tests/test_detect_features_compiled.py",  # (the Python reference against the extension)
    "tests/test_detect_features_reference.py",
    "tests/test_pipeline_lookahead.py",
)
LASERSCAN = ("tests/test_io_laserscan_fast.py",)
VIEW = ("tests/test_viz_acceptance.py",)
EVAL = ("tests/test_eval_cli.py",)
CSA_RULES = ("tests/test_track_csa.py",)
PEOPLE_BG = ("tests/test_background_histogram.py", "tests/test_background_histogram_compiled.py")
LEARN_PEOPLE = ("tests/test_pipeline_leg_foreground.py",)
GROUP_SIZE = ("tests/test_groups_size_resolved.py",)
MHT_CORE = ("tests/test_track_mht_core.py",)
MHT_STEP = (
    "tests/test_track_mht_core.py",
    "tests/test_track_mht_regression.py",
    "tests/test_track_legs.py",
)
DIAGNOSE = ("tests/test_eval_suite.py",)
FEET_BEAMS = ("tests/test_pf_feet_beams.py",)
FEET_HEIGHT = ("tests/test_laser_height_feet.py",)
HALVES = (
    "tests/test_track_groups.py::test_the_halves_of_a_split_keep_their_ids_by_position",
    "tests/test_track_groups.py::test_a_half_seen_alone_after_the_halves_swapped_keeps_its_persons_id",
    "tests/test_track_groups.py",
)
SETTINGS = ("tests/test_paper_settings.py",)
MOTION_MEDIAN = ("tests/test_pipeline_motion_median.py",)
SEGMENTS = (
    "tests/test_detect_segmentation.py",
    "tests/test_detect_segment_block.py",
    "tests/test_detect_block_compiled.py",
)
BLOBS = ("tests/test_pipeline_moving_blobs.py", "tests/test_pipeline_leg_foreground.py")
SHADOW = ("tests/test_track_groups_occlusion.py",)
TORSO = ("tests/test_pipeline_torso_blobs.py",)
LEG_RUNS = ("tests/test_pipeline_leg_runs.py",)
LIVE_FRAME = ("tests/test_live_frame.py",)
HANDOVER = ("tests/test_track_groups_handover.py",)
COAST = ("tests/test_track_groups_coast.py",)
FEET_SURFACE = ("tests/test_pf_feet_surface.py",)
TRUTH_BAG = ("tests/test_io_truth_bag.py", "tests/test_eval_followed.py")
PAPER_FEATURES = ("tests/test_paper_features.py",)
PAPER_ADABOOST = ("tests/test_paper_adaboost.py",)
PAPER_LEGS = ("tests/test_paper_legs.py",)

M = "tracking/groups/model.py"
I = "tracking/groups/interaction.py"  # noqa: E741 (a path, not a number)
CP = "tracking/csa/params.py"
CV = "tracking/csa/viterbi.py"
CC = "tracking/csa/clusters.py"
CT = "tracking/csa/tracker.py"
F = "tracking/particle/feet.py"
U = "tracking/particle/upper_body.py"
A = "identity/appearance.py"
O = "tracking/particle/objects.py"  # noqa: E741 (a path, not a letter)
G = "evaluation/groups.py"
L = "tracking/mht/listing.py"
H = "background/beam_histogram.py"
R = "io/ros1_reader.py"
PT = "tracking/person_tracks.py"
K = "tracking/kalman.py"
PM = "tracking/point_model.py"
LS = "io/laserscan_ros1.py"
MC = "tracking/mht/core.py"
GO = "tracking/groups/observations.py"
GS = "tracking/groups/occlusion.py"
TB = "pipeline/torso_blobs.py"
LR = "pipeline/leg_runs.py"
LC = "live/choice.py"
GHO = "tracking/groups/handover.py"
GC = "tracking/groups/coast.py"
GT = "tracking/groups/tracker.py"
FT = "detection/features.py"
AB = "detection/adaboost.py"
GD = "../../benchmarks/gnn_diagnose.py"  # (a benchmark script, beside src/ in the copy)

MUTANTS: tuple[Mutant, ...] = (
    # ---- 000 group tracker (Sec. 4)
    Mutant(
        "merge-prior-pc1",
        "000 eq. 32 (merge: p_G N_ij / p_C^2)",
        I,
        "ratio = self._log_pg + ll - 2.0 * self._log_pc",
        "ratio = self._log_pg + ll - 1.0 * self._log_pc",
        GROUPS,
    ),
    Mutant(
        "split-prior-no-pc",
        "000 eq. 32 (split: p_S / p_C)",
        I,
        'events.append(Event("split", (t,), self._log_ps - self._log_pc))',
        'events.append(Event("split", (t,), self._log_ps))',
        GROUPS,
    ),
    Mutant(
        "merge-weights-equal",
        "000 eqs. 17-18 (w = |P_i| / |P_ij|)",
        M,
        "w_i, w_j = n_points_i / total, n_points_j / total",
        "w_i, w_j = 0.5, 0.5",
        GROUPS,
    ),
    Mutant(
        "merge-cov-weights-not-squared",
        "000 eq. 18 (w^2)",
        M,
        "cov[:4, :4] = w_i**2 * cov_i[:4, :4] + w_j**2 * cov_j[:4, :4]",
        "cov[:4, :4] = w_i * cov_i[:4, :4] + w_j * cov_j[:4, :4]",
        GROUPS,
    ),
    Mutant(
        "merge-cross-cov-zero",
        "000 eq. 18 (size/kinematics cross-covariance)",
        M,
        "cross = w_i * cov_i[:4, 4] + w_j * cov_j[:4, 4]",
        "cross = 0.0 * cov_i[:4, 4]",
        GROUPS,
    ),
    Mutant(
        "merge-size-variance-mean",
        "000 Sec. 4.2.3 (merged sizes' variances add)",
        M,
        "cov[4, 4] = cov_i[4, 4] + cov_j[4, 4]",
        "cov[4, 4] = 0.5 * (cov_i[4, 4] + cov_j[4, 4])",
        GROUPS,
    ),
    Mutant(
        "merge-size-max",
        "000 Sec. 4.2.3 (merged sizes add)",
        M,
        "mean[4] = mean_i[4] + mean_j[4]",
        "mean[4] = max(mean_i[4], mean_j[4])",
        GROUPS,
    ),
    Mutant(
        "split-size-whole",
        "000 Sec. 4.2.3 (a split half has n/2)",
        M,
        "out[4] = 0.5 * out[4]",
        "out[4] = 1.0 * out[4]",
        GROUPS,
    ),
    Mutant(
        "eq23-no-point-noise",
        "000 eq. 23 (S = H C H^T + R_l)",
        M,
        "s = covs[:, :2, :2] + self.s.r_point  # eq. 23",
        "s = covs[:, :2, :2] + 0.0 * self.s.r_point  # eq. 23",
        GROUPS,
    ),
    Mutant(
        "eq19-max",
        "000 eq. 19 (min of the two directed distances)",
        M,
        "return np.asarray(np.minimum(z_to_p, p_to_z).T)  # eq. 19",
        "return np.asarray(np.maximum(z_to_p, p_to_z).T)  # eq. 19",
        GROUPS,
    ),
    Mutant(
        "eq19-one-direction",
        "000 eq. 19 (both directions)",
        M,
        "return np.asarray(np.minimum(z_to_p, p_to_z).T)  # eq. 19",
        "return np.asarray(np.asarray(z_to_p).T)  # eq. 19",
        GROUPS,
    ),
    Mutant(
        "eq21-cross-term-sign",
        "000 eq. 21 (Mahalanobis D with a non-diagonal S)",
        M,
        "tmp = np.multiply(dx, (2.0 * ds01)[col_owner], out=dx)",
        "tmp = np.multiply(dx, (-2.0 * ds01)[col_owner], out=dx)",
        GROUPS,
    ),
    Mutant(
        "eq24-normaliser-det",
        "000 eq. 24 (1 / (2 pi sqrt det S))",
        M,
        "log_norm = _LOG_2PI_NEG - 0.5 * np.log(ddet)",
        "log_norm = _LOG_2PI_NEG - 1.0 * np.log(ddet)",
        GROUPS,
    ),
    Mutant(
        "eq24-normaliser-det-one-by-one",
        "000 eq. 24 (1 / (2 pi sqrt det S), the unbatched sum)",
        M,
        "log_norm = np.array([_LOG_2PI_NEG - 0.5 * math.log(d) for d in ddet.tolist()])",
        "log_norm = np.array([_LOG_2PI_NEG - 1.0 * math.log(d) for d in ddet.tolist()])",
        GROUPS,
    ),
    Mutant(
        "share-parts-always",
        "000 eq. 24 per part (share_parts = false)",
        M,
        "w = obs.share[cols_m][None, :] if self.s.share_parts else np.ones((1, cols_m.size))",
        "w = obs.share[cols_m][None, :]",
        GROUPS,
    ),
    Mutant(
        "eq37-v-ignored",
        "000 eqs. 36-37 (lambda = p / V)",
        I,
        "log_v = math.log(self.area)",
        "log_v = 0.0 * math.log(self.area)",
        GROUPS,
    ),
    Mutant(
        "eq37-v-not-per-scan",
        "000 eqs. 36-37 (V the sensor's field of view)",
        "tracking/groups/tracker.py",
        "self.label_model.area = self._visible_area(frame)",
        "self.label_model.area = 1.0",
        GROUPS,
    ),
    Mutant(
        "eq24-exponent",
        "000 eq. 24 (exp(-d_HD^2 / 2))",
        M,
        "sub_ll = w * (lpm + log_norm[:, None] - 0.5 * d_hd**2) - lpm",
        "sub_ll = w * (lpm + log_norm[:, None] - 1.0 * d_hd**2) - lpm",
        GROUPS,
    ),
    Mutant(
        "gate-on-distance",
        "000 Sec. 4.4 (gate on d_HD^2)",
        M,
        "ok = sub_near & (d_hd**2 <= self.s.gate_sq)",
        "ok = sub_near & (d_hd <= self.s.gate_sq)",
        GROUPS,
    ),
    Mutant(
        "eq25-no-dp-shortening",
        "000 eq. 25 (dx shortened by d_P)",
        M,
        "np.divide(d_p, scale, out=scale)",
        "np.divide(0.0, scale, out=scale)",
        GROUPS,
    ),
    Mutant(
        "eq25-no-velocity",
        "000 eq. 25 (velocity difference)",
        M,
        "star[2] = mean_i[2] - mean_j[2]  # eq. 25",
        "star[2] = 0.0  # eq. 25",
        GROUPS,
    ),
    Mutant(
        "eq26-one-covariance",
        "000 eq. 26 (C_i + C_j)",
        M,
        "s = cov_i[:4, :4] + cov_j[:4, :4]",
        "s = cov_i[:4, :4] + cov_i[:4, :4]",
        GROUPS,
    ),
    Mutant(
        "eq26-mean-not-min",
        "000 eq. 26 (min over point pairs)",
        M,
        'return float(np.einsum("ji,ji->i", flat, sol).min())  # eq. 26',
        'return float(np.einsum("ji,ji->i", flat, sol).mean())  # eq. 26',
        GROUPS,
    ),
    Mutant(
        "eq27-normaliser",
        "000 eq. 27 ((2 pi)^2)",
        M,
        "return -2.0 * math.log(2.0 * math.pi) - 0.5 * math.log(det) - 0.5 * d_min_sq",
        "return -1.0 * math.log(2.0 * math.pi) - 0.5 * math.log(det) - 0.5 * d_min_sq",
        GROUPS,
    ),
    Mutant(
        "eq27-exponent",
        "000 eq. 27 (exp(-d_min^2 / 2))",
        M,
        "return -2.0 * math.log(2.0 * math.pi) - 0.5 * math.log(det) - 0.5 * d_min_sq",
        "return -2.0 * math.log(2.0 * math.pi) - 0.5 * math.log(det) - 1.0 * d_min_sq",
        GROUPS,
    ),
    Mutant(
        "eq30-no-observation-noise",
        "000 eq. 30 (S = H~ C H~^T + R)",
        M,
        "s = hc[:, :, [0, 1, 4]] + r  # H~ C H~^T + R (T, 3, 3)",
        "s = hc[:, :, [0, 1, 4]] + 0.1 * r  # H~ C H~^T + R (T, 3, 3)",
        GROUPS,
    ),
    Mutant(
        "eq29-no-covariance-update",
        "000 eq. 29 (C - K H~ C)",
        M,
        'new_covs = covs - np.einsum("tij,tik->tjk", gain_t, hc)',
        'new_covs = covs - 0.0 * np.einsum("tij,tik->tjk", gain_t, hc)',
        GROUPS,
    ),
    Mutant(
        "eq31-size-not-observed",
        "000 eq. 31 (n_hs observed)",
        M,
        "z = np.column_stack([centroids, n_hs])",
        "z = np.column_stack([centroids, means[:, 4]])",
        GROUPS,
    ),
    Mutant(
        "predict-no-velocity",
        "000 Sec. 4.2.3 (constant velocity A)",
        M,
        "a[:, 0, 2] = a[:, 1, 3] = dt",
        "a[:, 0, 2] = a[:, 1, 3] = 0.0 * dt",
        GROUPS,
    ),
    Mutant(
        "predict-q-unscaled",
        "000 Sec. 4.2.3 (Q per period)",
        M,
        "+ self.s.q[None] * (dt / self.s.period)[:, None, None]",
        "+ self.s.q[None] * (0.0 * dt + 1.0)[:, None, None]",
        GROUPS,
    ),
    Mutant(
        "eq16-size-one",
        "000 eq. 16 (n = n_hs)",
        M,
        "means[:, 4] = obs.n_hs[idx]",
        "means[:, 4] = 1.0",
        GROUPS,
    ),
    Mutant(
        "eq36-occluded-obsolete-swapped",
        "000 eq. 36 (p_O, p_T)",
        I,
        "self._lp = np.log(np.array([p_m, p_o, p_t]))",
        "self._lp = np.log(np.array([p_m, p_t, p_o]))",
        GROUPS,
    ),
    Mutant(
        "eq36-new-false-swapped",
        "000 eq. 36 (p_N, p_F)",
        I,
        "self._log_p_new = math.log(p_n)",
        "self._log_p_new = math.log(p_f)",
        GROUPS,
    ),
    Mutant(
        "must-match-may-occlude",
        "000 Sec. 4.4 (split/merged tracks must be matched)",
        I,
        "self._must = np.array([math.log(p_m), -np.inf, -np.inf])",
        "self._must = np.array([math.log(p_m), math.log(p_o), -np.inf])",
        GROUPS,
    ),
    Mutant(
        "models-worst-first",
        "000 Sec. 4.4 (the likeliest models by eq. 32)",
        I,
        "rec(k + 1, used | ids, (*chosen, e), score + e.log_ratio)",
        "rec(k + 1, used | ids, (*chosen, e), score - e.log_ratio)",
        GROUPS,
    ),
    Mutant(
        "recluster-farthest",
        "000 Sec. 4.3 (nearest-track rule)",
        I,
        "return np.asarray(np.argmin(per_unit, axis=1), dtype=np.int64)",
        "return np.asarray(np.argmax(per_unit, axis=1), dtype=np.int64)",
        GROUPS,
    ),
    # ---- 002 Cluster Sorting
    Mutant(
        "csa-merge-two-points",
        "002 Sec. 2 (objects sharing one measurement merge)",
        CC,
        "shared = (g @ g.T) > 0  # share at least one measurement",
        "shared = (g @ g.T) > 1  # share at least one measurement",
        CSA,
    ),
    Mutant(
        "csa-split-one-pair-apart",
        "002 split condition 2 (every pair apart)",
        CC,
        "return separated == n_sub * (n_sub - 1) // 2, labels",
        "return separated >= 1, labels",
        CSA,
    ),
    Mutant(
        "csa-split-fewer-subclusters",
        "002 split condition 1 (as many sub-clusters as people)",
        CC,
        "if n_sub != n_people:",
        "if n_sub < n_people:",
        CSA,
    ),
    Mutant(
        "csa-leader-double-radius",
        "002 Sec. 2 (leader clustering at 1.5 m)",
        CC,
        "near = np.linalg.norm(pts[free] - first, axis=1) < distance",
        "near = np.linalg.norm(pts[free] - first, axis=1) < 2.0 * distance",
        CSA,
    ),
    Mutant(
        "csa-viterbi-no-path-score",
        "002 Sec. 2 / 2004a (Viterbi path scores)",
        CV,
        "total = np.where(inside, np.asarray(scores, dtype=np.float64)[:, None] + loglik, -np.inf)",
        "total = np.where(inside, 0.0 * np.asarray(scores)[:, None] + loglik, -np.inf)",
        CSA,
    ),
    Mutant(
        "csa-fragment-rule-always",
        "002 Sec. 2 (the cluster remembers everyone who merged)",
        CT,
        "cids = {clusters[k].cid for k in objs_c} if p.fragment_rule else set()",
        "cids = {clusters[k].cid for k in objs_c}",
        CSA,
    ),
    Mutant(
        "csa-kfa-first-point",
        "002 Sec. 2 (KFA: mean of the selected measurements)",
        CT,
        "centre = z[sel].mean(axis=0)",
        "centre = z[sel][0]",
        CSA,
    ),
    Mutant(
        "csa-gate-cross-term-sign",
        "002 Sec. 2 (Mahalanobis validation gate)",
        CV,
        "d2 = (d[:, None] * vx * vx - 2.0 * b[:, None] * vx * vy + a[:, None] * vy * vy)",
        "d2 = (d[:, None] * vx * vx + 2.0 * b[:, None] * vx * vy + a[:, None] * vy * vy)",
        CSA,
    ),
    Mutant(
        "csa-gate-half",
        "002 Sec. 2 (chi-square gate -2 ln(1 - p))",
        CP,
        "return -2.0 * math.log1p(-self.gate_probability)",
        "return -1.0 * math.log1p(-self.gate_probability)",
        CSA,
    ),
    # ---- 002 colour re-identification
    Mutant(
        "eq4-mean-halfway",
        "002 eq. 4 (running mean)",
        A,
        "new_mean = k / (k + 1) * self.mean + y / (k + 1)  # eq. 4",
        "new_mean = 0.5 * self.mean + 0.5 * y  # eq. 4",
        REID,
    ),
    Mutant(
        "eq5-biased",
        "002 eq. 5 (unbiased covariance)",
        A,
        "np.outer(r, r) / k + (k - 1) / k * self.covariance + np.outer(delta, delta)",
        "np.outer(r, r) / (k + 1) + (k - 1) / k * self.covariance + np.outer(delta, delta)",
        REID,
    ),
    Mutant(
        "eq5-no-mean-shift",
        "002 eq. 5 (delta delta^T term)",
        A,
        "np.outer(r, r) / k + (k - 1) / k * self.covariance + np.outer(delta, delta)",
        "np.outer(r, r) / k + (k - 1) / k * self.covariance",
        REID,
    ),
    Mutant(
        "eq6-no-logdet",
        "002 eq. 6 (|Sigma|^-1/2)",
        A,
        "return -0.5 * d2 - 0.5 * (b * LOG_2PI + logdet)[:, None]",
        "return -0.5 * d2 - 0.5 * (b * LOG_2PI + 0.0 * logdet)[:, None]",
        REID,
    ),
    Mutant(
        "hue-bins-not-centred",
        "002 Table 1 (bins centred on the colours)",
        A,
        "idx = np.floor((np.mod(h, 2.0 * math.pi) + 0.5 * width) / width)",
        "idx = np.floor((np.mod(h, 2.0 * math.pi) + 0.0 * width) / width)",
        REID,
    ),
    Mutant(
        "reid-ignores-min-observations",
        "002 eq. 7 (observations after the crossing)",
        "identity/reid.py",
        "enough = all(c.n_obs.get(t, 0) >= p.min_observations for t in present)",
        "enough = True",
        REID,
    ),
    # ---- 004 particle filters
    Mutant(
        "feet-no-repelling",
        "004 Sec. 3 (repelling term)",
        F,
        "lik = lik * repelling(mids, est, p.sigma_repel)",
        "lik = lik * 1.0",
        PF,
    ),
    Mutant(
        "feet-no-body-offset",
        "004 eqs. 1-2 (body ahead of the feet midpoint)",
        F,
        "body = self.midpoints() + body_offset(st)",
        "body = self.midpoints() + 0.0 * body_offset(st)",
        PF,
    ),
    Mutant(
        "eq1-feet-swapped",
        "004 eq. 1 (left foot in the second half period)",
        F,
        "left = np.mod(g1, TWO_PI) > np.pi",
        "left = np.mod(g1, TWO_PI) < np.pi",
        PF,
    ),
    Mutant(
        "eq2-sine",
        "004 eq. 2 (s |cos g_t - cos g_t-1|)",
        F,
        "move = states[..., S] * np.abs(np.cos(g1) - np.cos(g0))",
        "move = states[..., S] * np.abs(np.sin(g1) - np.sin(g0))",
        PF,
    ),
    Mutant(
        "eq3-kernel-width",
        "004 eq. 3 (exp(-d^2 / (2 delta^2)))",
        F,
        "kernel = np.exp(np.maximum(d2, 0.0) * np.float32(-0.5 / (delta * delta)))",
        "kernel = np.exp(np.maximum(d2, 0.0) * np.float32(-1.0 / (delta * delta)))",
        PF,
    ),
    Mutant(
        "eq4-no-floor",
        "004 eq. 4 (max(., P_0))",
        F,
        "return np.asarray(np.maximum(total, p0), dtype=np.float64)",
        "return np.asarray(total + 0.0 * p0, dtype=np.float64)",
        PF,
    ),
    Mutant(
        "eq6-sign",
        "004 eq. 6 (s_d + s cos gamma)",
        F,
        "r = s_d + states[..., S] * np.cos(states[..., GAMMA])",
        "r = s_d - states[..., S] * np.cos(states[..., GAMMA])",
        PF,
    ),
    Mutant(
        "eq7-no-stride",
        "004 eq. 7 (o_l o_r o_b)",
        F,
        "return o_l * o_r * o_b",
        "return o_l * o_r",
        PF,
    ),
    Mutant(
        "body-offset-formula",
        "004 eqs. 1-2 (midpoint moves (s/2)(1 - cos phi))",
        F,
        "ahead = states[..., S] * (phi / np.pi - 0.5 * (1.0 - np.cos(phi)))",
        "ahead = states[..., S] * (phi / np.pi - 1.0 * (1.0 - np.cos(phi)))",
        PF,
    ),
    Mutant(
        "eq8-sine",
        "004 eq. 8 (x += cos theta v dt)",
        U,
        "out[..., X] += np.cos(states[..., THETA]) * step",
        "out[..., X] += np.sin(states[..., THETA]) * step",
        PF,
    ),
    Mutant(
        "eq9-zeta",
        "004 eq. 9 (exp(-d^2 / zeta^2))",
        U,
        "kernel = np.exp(np.maximum(d2, 0.0) * np.float32(-1.0 / (zeta * zeta)))",
        "kernel = np.exp(np.maximum(d2, 0.0) * np.float32(-0.5 / (zeta * zeta)))",
        PF,
    ),
    # ---- extensions: CSA confirmation, feet-pf cell refresh and shared clustering, the
    # proxemic group truth, the leg MHT's listing budget, the per-beam histogram's
    # foreground of a frame, the ROS 1 reader's MD5 check
    Mutant(
        "csa-confirm-no-reset",
        "CSA confirm_scans (a miss restarts the count)",
        CT,
        "hits = t.hits if t.hits >= p.confirm_scans else 0",
        "hits = t.hits",
        CSA_CONFIRM,
    ),
    Mutant(
        "csa-confirm-off-by-one",
        "CSA confirm_scans (reported at the n-th scan)",
        CT,
        "return t.born == -math.inf or t.hits >= self.params.confirm_scans",
        "return t.born == -math.inf or t.hits > self.params.confirm_scans",
        CSA_CONFIRM,
    ),
    Mutant(
        "csa-confirm-lost-on-miss",
        "CSA confirm_scans (a confirmed target stays so)",
        CT,
        "hits = t.hits if t.hits >= p.confirm_scans else 0",
        "hits = 0",
        CSA_CONFIRM,
    ),
    Mutant(
        "feet-cell-refresh-inverted",
        "feet-pf cell_refresh (refresh when farther)",
        F,
        "(count >= p.still_points) & (off > p.cell_refresh)",
        "(count >= p.still_points) & (off < p.cell_refresh)",
        FEET_REFRESH,
    ),
    Mutant(
        "feet-cell-refresh-split-at-feet",
        "feet-pf cell_refresh (feet from the cell's centre)",
        F,
        "self._refresh(int(f), two_feet(pts[owner == f], mean[f], cov[f]))",
        "self._refresh(int(f), two_feet(pts[owner == f], est[f], cov[f]))",
        FEET_REFRESH,
    ),
    Mutant(
        "feet-refresh-share-complement",
        "feet-pf refresh_share (share restarted)",
        F,
        "k = round(p.refresh_share * p.particles)",
        "k = round((1.0 - p.refresh_share) * p.particles)",
        FEET_REFRESH,
    ),
    Mutant(
        "kept-labels-pieces-one-object",
        "feet-pf kept_labels (kept pieces linked again)",
        O,
        "sub[part] = n + again",
        "sub[part] = n + 0 * again",
        KEPT,
    ),
    Mutant(
        "kept-labels-numbered-by-label",
        "feet-pf kept_labels (numbered by first point)",
        O,
        'rank[np.argsort(first, kind="stable")] = np.arange(first.size)',
        "rank[np.arange(first.size)] = np.arange(first.size)",
        KEPT,
    ),
    Mutant(
        "proxemic-near-or-alike",
        "000 Sec. 4.2 proxemic truth (near and alike)",
        G,
        "if np.any(near & alike):",
        "if np.any(near | alike):",
        PROXEMIC,
    ),
    Mutant(
        "proxemic-body-centres",
        "000 Sec. 4.2 proxemic truth (leg to leg)",
        G,
        "if not np.all(np.isfinite(legs)):",
        "if np.all(np.isfinite(legs)):",
        PROXEMIC,
    ),
    Mutant(
        "proxemic-every-leg",
        "000 Sec. 4.2 proxemic truth (any leg pair)",
        G,
        "near = near.reshape(len(a), 2, len(b), 2).any(axis=(1, 3))",
        "near = near.reshape(len(a), 2, len(b), 2).all(axis=(1, 3))",
        PROXEMIC,
    ),
    Mutant(
        "listing-budget-never-murty",
        "leg MHT listing budget (out of steps: Murty)",
        L,
        "if budget <= 0:\n            return None\n        steps = budget",
        "if budget <= 0:\n            return None\n        steps = 0",
        LISTING,
    ),
    Mutant(
        "listing-budget-off-by-one",
        "leg MHT listing budget (steps counted)",
        L,
        "if self.left < 0:\n            raise _OutOfStepsError\n        super()._measurements(",
        "if self.left < -1:\n            raise _OutOfStepsError\n        super()._measurements(",
        LISTING,
    ),
    Mutant(
        "listing-budget-tracks-free",
        "leg MHT listing budget (a track labelled is a step)",
        L,
        "self.left -= 1\n        if self.left < 0:\n            raise _OutOfStepsError\n"
        "        super()._tracks(",
        "super()._tracks(",
        LISTING,
    ),
    Mutant(
        "listing-budget-everywhere",
        "leg MHT listing budget (only over the limit)",
        L,
        "steps = 0  # listing steps allowed (0: no budget)",
        "steps = budget  # listing steps allowed (0: no budget)",
        LISTING,
    ),
    Mutant(
        "histogram-one-laser-first-points",
        "004 Sec. 2 histogram foreground (per point's beam)",
        H,
        "one: NDArray[np.bool_] = by_name[pts.sensors[0]][pts.beams]",
        "one: NDArray[np.bool_] = by_name[pts.sensors[0]][: len(pts)]",
        HISTOGRAM,
    ),
    Mutant(
        "histogram-one-mask-for-all-lasers",
        "004 Sec. 2 histogram foreground (per laser)",
        H,
        "if len(pts.sensors) == 1 and pts.sensors[0] in by_name:",
        "if pts.sensors[0] in by_name:",
        HISTOGRAM,
    ),
    Mutant(
        "ros1-md5-skipped",
        "ROS 1 reader (message definitions vs MD5 sums)",
        R,
        "if conn.digest:\n            digests[conn.msgtype] = conn.digest",
        "if not conn.digest:\n            digests[conn.msgtype] = conn.digest",
        ROS1,
    ),
    Mutant(
        "ros1-lazy-typestore-any-standard",
        "ROS 1 reader: a bag with one standard type among others defers its typestore",
        R,
        "            if key not in TYPESTORES and all(",
        "            if key not in TYPESTORES and any(",
        ("tests/test_io_ros1_lazy_typestore.py",),
    ),
    Mutant(
        "ros1-lazy-typestore-empty-is-standard",
        "ROS 1 reader: a type without connections counts as standard",
        R,
        "        return bool(digests) and all((msgtype, d) in standard for d in digests)",
        "        return all((msgtype, d) in standard for d in digests)",
        ("tests/test_io_ros1_lazy_typestore.py",),
    ),
    # ---- code added since: walked candidates, one-step Kalman prediction, block features,
    # direct LaserScan decoding, the view's truth transform, the evaluation's warning
    Mutant(
        "walked-miss-confirmed-too",
        "person tracks: walked_miss (unconfirmed only)",
        PT,
        "and not person.confirmed\n                and any(self._walked(",
        "and any(self._walked(",
        WALKED,
    ),
    Mutant(
        "walked-static-gate-strict",
        "person tracks: walked place static <= arrival_slack",
        PT,
        "float(self._static(person.mean[None, :2])[0]) <= p.arrival_slack",
        "float(self._static(person.mean[None, :2])[0]) < p.arrival_slack",
        WALKED,
    ),
    Mutant(
        "young-track-anywhere",
        "person tracks: a young leg judged on its whole path only when young",
        PT,
        "young and params.moving_min_detections and len(path) >= params.moving_min_detections",
        "params.moving_min_detections and len(path) >= params.moving_min_detections",
        WALKED,
    ),
    Mutant(
        "young-track-two-detections",
        "person tracks: moving_min_detections detections (3), not one fewer",
        PT,
        "young and params.moving_min_detections and len(path) >= params.moving_min_detections",
        "young and params.moving_min_detections and len(path) >= params.moving_min_detections - 1",
        WALKED,
    ),
    Mutant(
        "walked-no-speed",
        "person tracks: walked (moving_speed x elapsed)",
        PT,
        "return net >= self.params.walked_distance and net >= self.params.moving_speed * (",
        "return net >= self.params.walked_distance or net >= self.params.moving_speed * (",
        WALKED,
    ),
    Mutant(
        "walked-time-since-zero",
        "person tracks: walked (time since first detection)",
        PT,
        "self._stamp - t0\n        )",
        "self._stamp\n        )",
        WALKED,
    ),
    Mutant(
        "young-credit-unbounded",
        "person tracks: young_credit at most the young path's earlier detections",
        PT,
        "return min(person.one_leg_scans, earlier) * (steps[TWO] - steps[ONE])",
        "return person.one_leg_scans * (steps[TWO] - steps[ONE])",
        WALKED,
    ),
    Mutant(
        "young-credit-any-distance",
        "person tracks: young_credit from moving_speed x moving_time on",
        PT,
        "reach = p.moving_speed * p.moving_time",
        "reach = 0.0",
        WALKED,
    ),
    Mutant(
        "young-credit-mature-paths",
        "person tracks: young_credit for young paths only",
        PT,
        "if not path or len(path) < 2 or path[0][0] <= path[-1][0] - p.moving_time + 1e-9:",
        "if not path or len(path) < 2:",
        WALKED,
    ),
    Mutant(
        "young-credit-misses-counted",
        "person tracks: young_credit counts one-leg scans, not misses",
        PT,
        "elif evidence == ONE and not person.seen_moving:",
        "elif not person.seen_moving:",
        WALKED,
    ),
    Mutant(
        "young-credit-every-scan",
        "person tracks: young_credit when first seen moving only",
        PT,
        "if not person.seen_moving:\n                    person.seen_moving = True\n",
        "if True:\n                    person.seen_moving = True\n",
        WALKED,
    ),
    Mutant(
        "young-credit-static-slack",
        "person tracks: young_credit where the leg has just come (not arrival_slack)",
        PT,
        "if float(self._static(np.array([[x1, y1]]))[0]) > came + 1e-9:",
        "if float(self._static(np.array([[x1, y1]]))[0]) > p.arrival_slack:",
        WALKED,
    ),
    Mutant(
        "young-credit-came-at-first",
        "person tracks: young_credit static since the detection before, not the first",
        PT,
        "came = path[-1][0] - path[-2][0]",
        "came = path[-1][0] - path[0][0]",
        WALKED,
    ),
    Mutant(
        "furniture-two-legs",
        "person tracks: furniture_scans count three legs, not a person's two",
        PT,
        "if len(posts) < 3:",
        "if len(posts) < 2:",
        PERSON,
    ),
    Mutant(
        "furniture-radius-unsquared",
        "person tracks: legs within furniture_radius (squared distances)",
        PT,
        'near = np.einsum("mnk,mnk->mn", d, d) <= p.furniture_radius**2',
        'near = np.einsum("mnk,mnk->mn", d, d) <= p.furniture_radius',
        PERSON,
    ),
    Mutant(
        "furniture-verdict-late",
        "person tracks: a place is judged furniture at furniture_scans scans, not one more",
        PT,
        "if q.posts == p.furniture_scans:",
        "if q.posts == p.furniture_scans + 1:",
        PERSON,
    ),
    Mutant(
        "furniture-walked-too",
        "person tracks: furniture only for people that never travelled min_travel",
        PT,
        "if q.travelled < p.min_travel\n                and (q.posts >= p.furniture_scans or",
        "if (q.posts >= p.furniture_scans or",
        PERSON,
    ),
    Mutant(
        "furniture-place-forgotten",
        "person tracks: a furniture verdict holds for its place (the chair born again)",
        PT,
        "(q.posts >= p.furniture_scans or self._on_furniture_place(q))",
        "(q.posts >= p.furniture_scans)",
        PERSON,
    ),
    Mutant(
        "furniture-place-radius-squared",
        "person tracks: a judged place holds within furniture_radius",
        PT,
        "if math.hypot(x - fx, y - fy) <= r]",
        "if math.hypot(x - fx, y - fy) <= r * r]",
        PERSON,
    ),
    Mutant(
        "furniture-place-not-static",
        "person tracks: a furniture verdict holds while its place is static",
        PT,
        "return bool(near) and bool((self._static(np.array(near)) > 0.0).any())",
        "return bool(near)",
        PERSON,
    ),
    Mutant(
        "furniture-any-speed",
        "person tracks: posts counted only for a person slower than furniture_speed",
        PT,
        "if vx * vx + vy * vy < p.furniture_speed**2 or all(",
        "if True or all(",
        PERSON,
    ),
    Mutant(
        "furniture-any-leg-speed",
        "person tracks: a fast person's posts counted only when its legs are slower than "
        "furniture_leg_speed",
        PT,
        "< p.furniture_leg_speed for leg in posts",
        "< 1e6 for leg in posts",
        PERSON,
    ),
    Mutant(
        "furniture-leg-speed-any-leg",
        "person tracks: every leg near a fast person slower than furniture_leg_speed",
        PT,
        "furniture_speed**2 or all(",
        "furniture_speed**2 or any(",
        PERSON,
    ),
    Mutant(
        "furniture-neighbours-legs-too",
        "person tracks: furniture legs not another person's",
        PT,
        "if owner.get(seen[j].track_id, q.person_id) == q.person_id",
        "if owner.get(seen[j].track_id, q.person_id) >= 0",
        PERSON,
    ),
    Mutant(
        "kalman-one-step-any-steps",
        "Kalman: one shared step only when all equal",
        K,
        "return d if steps.count(d) == len(steps) else None",
        "return d",
        KALMAN,
    ),
    Mutant(
        "kalman-one-step-q-pv",
        "Kalman: one-step process noise (q d^2 / 2)",
        K,
        "pp, pv, vv = a * d**3 / 3.0, a * (d * d) / 2.0, a * d\n    rows = [",
        "pp, pv, vv = a * d**3 / 3.0, a * (d * d) / 3.0, a * d\n    rows = [",
        KALMAN,
    ),
    Mutant(
        "kalman-one-step-coast-cov",
        "Kalman: one-step coasting covariance (F_c P F_c')",
        K,
        "return pm, both[0], cm, both[1]",
        "return pm, both[0], cm, both[0]",
        KALMAN,
    ),
    Mutant(
        "kalman-rows-cubes-by-numpy",
        "Kalman rows: a few steps cubed by Python's pow, as the reference's few-track path",
        K,
        "cubes: list[float] = [e**3 for e in dts] if n <= SMALL_BATCH else (steps**3).tolist()",
        "cubes: list[float] = (steps**3).tolist()",
        KALMAN_ROWS,
    ),
    Mutant(
        "kalman-rows-cubes-by-pow",
        "Kalman rows: many different steps cubed by numpy's power, as the reference's",
        K,
        "cubes: list[float] = [e**3 for e in dts] if n <= SMALL_BATCH else (steps**3).tolist()",
        "cubes: list[float] = [e**3 for e in dts]",
        KALMAN_ROWS,
    ),
    Mutant(
        "kalman-rows-decay-by-math-exp",
        "Kalman rows: the shared step's decay by numpy's exp",
        K,
        "k = float(np.exp(np.array((-d / tau,)))[0])\n        if len(_DECAYS)",
        "k = math.exp(-d / tau)\n        if len(_DECAYS)",
        KALMAN_ROWS,
    ),
    Mutant(
        "kalman-rows-half-log-det",
        "Kalman rows: loglik = -0.5 d2 - log 2 pi - 0.5 log det S (the half)",
        K,
        "    det *= 0.5\n",
        "",
        KALMAN_ROWS,
    ),
    Mutant(
        "point-model-steps-negative",
        "point model: a node stamped after the scan steps 0 s (shared step)",
        PM,
        "if 0.0 <= d <= top and steps.count(d) == len(steps):",
        "if d <= top and steps.count(d) == len(steps):",
        KALMAN_ROWS,
    ),
    Mutant(
        "point-model-steps-max-dt",
        "point model: a shared step longer than max_dt is clipped",
        PM,
        "if 0.0 <= d <= top and steps.count(d) == len(steps):",
        "if 0.0 <= d and steps.count(d) == len(steps):",
        KALMAN_ROWS,
    ),
    Mutant(
        "features-step-across-segments",
        "block features: no step into a segment's first point",
        "detection/features.py",
        "t1[1:, 0] = steps\n        t1[off, 0] = 0.0",
        "t1[1:, 0] = steps",
        FEATURES,
    ),
    Mutant(
        "laserscan-trailing-bytes",
        "ROS 1 LaserScan decoding (to the last byte)",
        LS,
        "if at + 4 * m != size:",
        "if at + 4 * m > size:",
        LASERSCAN,
    ),
    Mutant(
        "laserscan-md5-ignored",
        "ROS 1 LaserScan decoding (standard type by MD5)",
        LS,
        'and getattr(conn, "digest", None) == LASERSCAN_MD5',
        'and getattr(conn, "digest", None) is not None',
        LASERSCAN,
    ),
    Mutant(
        "laserscan-intensities-offset",
        "ROS 1 LaserScan decoding (offsets)",
        LS,
        'intensities = np.frombuffer(raw, dtype="<f4", count=m, offset=at)',
        'intensities = np.frombuffer(raw, dtype="<f4", count=m, offset=at - 4)',
        LASERSCAN,
    ),
    Mutant(
        "view-truth-wrong-direction",
        "view: truth world -> sensor (inverse transform)",
        "viz/scene.py",
        'move = pose.inverse_transform_points if to == "sensor" else pose.transform_points',
        'move = pose.transform_points if to == "sensor" else pose.inverse_transform_points',
        VIEW,
    ),
    Mutant(
        "view-truth-velocity-unrotated-back",
        "view: truth velocity sensor -> world (R')",
        "viz/scene.py",
        'velocities=truth.velocities @ (rot if to == "sensor" else rot.T),',
        "velocities=truth.velocities @ rot,",
        VIEW,
    ),
    Mutant(
        "eval-nothing-matched-no-tracks",
        "evaluate: nothing matched needs tracks",
        "evaluation/report.py",
        "return c.matches == 0 and c.num_tracks > 0 and c.num_truth > 0",
        "return c.matches == 0 and c.num_truth > 0",
        EVAL,
    ),
    # ---- the CSA's rules for people walking off a cluster and for a moving laser
    Mutant(
        "csa-cut-free-legs-apart",
        "CSA cut_free (not within 1.5 m of the main paths)",
        CT,
        "            if gap <= p.subcluster_distance:"
        "  # leader clustering cut a person's legs apart\n"
        "                continue\n",
        "",
        CSA_RULES,
    ),
    Mutant(
        "csa-cut-free-min-points-off-by-one",
        "CSA cut_free (>= min_points estimates start a target)",
        CT,
        "if int(sel.sum()) < p.min_points:  # too few to start a target: dropped",
        "if int(sel.sum()) <= p.min_points:  # too few to start a target: dropped",
        CSA_RULES,
    ),
    Mutant(
        "csa-cut-free-few-kept",
        "CSA cut_free (fewer than min_points dropped)",
        CT,
        "            keep &= ~sel\n"
        "            if int(sel.sum()) < p.min_points:  # too few to start a target: dropped\n"
        "                continue\n",
        "            if int(sel.sum()) < p.min_points:  # too few to start a target: dropped\n"
        "                continue\n"
        "            keep &= ~sel\n",
        CSA_RULES,
    ),
    Mutant(
        "csa-moving-travel-still-laser",
        "CSA moving_travel (a moving laser only)",
        CT,
        "return not (self._moving and pid in self._unwalked)",
        "return pid not in self._unwalked",
        CSA_RULES,
    ),
    Mutant(
        "csa-moving-unseen-still-laser",
        "CSA moving_unseen (a moving laser only)",
        CT,
        "return not (self._moving and limit > 0 and stamp - t.last_seen > limit)",
        "return not (limit > 0 and stamp - t.last_seen > limit)",
        CSA_RULES,
    ),
    Mutant(
        "csa-lost-keep-reported",
        "CSA lost_keep (kept, not reported)",
        CT,
        "        if stamp - t.last_seen > self.params.max_unseen:\n            return False\n",
        "",
        CSA_RULES,
    ),
    Mutant(
        "csa-lost-keep-cluster-reported",
        "CSA lost_keep (a kept cluster is not reported)",
        CT,
        "if frame.stamp - c.last_seen > p.max_unseen:  # kept by lost_keep: not reported\n"
        "                continue\n",
        "if False:  # kept by lost_keep: reported\n                continue\n",
        CSA_RULES,
    ),
    Mutant(
        "csa-lost-keep-singles-only",
        "CSA lost_keep (clusters kept too)",
        CT,
        "if stamp - last_seen > p.max_unseen + p.lost_keep:\n                return None",
        "if stamp - last_seen > p.max_unseen:\n                return None",
        CSA_RULES,
    ),
    Mutant(
        "csa-split-apart-at-subcluster-distance",
        "CSA split_apart (002 condition 2: more than 3 m from every other sub-cluster)",
        CT,
        "if len(ms) == 1 and d[k].min() > p.separation_distance",
        "if len(ms) == 1 and d[k].min() > p.subcluster_distance",
        CSA_RULES,
    ),
    Mutant(
        "csa-split-apart-shared-subcluster",
        "CSA split_apart (a sub-cluster that is the main one of one person only)",
        CT,
        "if len(ms) == 1 and d[k].min() > p.separation_distance",
        "if d[k].min() > p.separation_distance",
        CSA_RULES,
    ),
    Mutant(
        "csa-coast-people-from-now",
        "CSA coast_people (a person without a time counts from the cluster's last scan)",
        CV,
        "continued.setdefault(o, before)  # its clock",
        "continued.setdefault(o, stamp)  # its clock",
        CSA_RULES,
    ),
    Mutant(
        "csa-coast-people-clock-not-kept",
        "CSA coast_people (a person counted into a cluster keeps the time it was first missed)",
        CV,
        "    for o in {int(o) for o in old_origin}:\n"
        "        continued.setdefault(o, before)  # its clock runs from the cluster's last scan\n"
        "    coast = [\n"
        "        o for o in sorted({int(o) for o in old_origin} - kept) if stamp - continued[o] "
        "<= max_unseen\n",
        "    coast = [\n"
        "        o for o in sorted({int(o) for o in old_origin} - kept) "
        "if stamp - continued.get(o, before) <= max_unseen\n",
        CSA_RULES,
    ),
    Mutant(
        "csa-coast-people-forever",
        "CSA coast_people (paths continued now restart the person's time)",
        CV,
        "    for o in kept:\n        continued[o] = stamp\n",
        "    for o in kept:\n        continued.setdefault(o, stamp)\n",
        CSA_RULES,
    ),
    Mutant(
        "csa-jump-back-any-points",
        "CSA jump_back (at least min_points points go back to the state before the jump)",
        CT,
        "(back := self._jump_back(before, z, free)).sum() >= p.min_points",
        "(back := self._jump_back(before, z, free)).sum() >= 1",
        CSA_RULES,
    ),
    Mutant(
        "csa-jump-back-forever",
        "CSA jump_back (the state before the jump is kept for max_unseen only)",
        CT,
        "if t.before is None or self._stamp - t.before[2] > self.params.max_unseen:",
        "if t.before is None:",
        CSA_RULES,
    ),
    Mutant(
        "csa-jump-back-seen-any",
        "CSA jump_back_seen (only a target with points in every scan for 0.5 s jumps back)",
        CT,
        "steady = t.last_seen - t.seen_since >= p.jump_back_seen",
        "steady = True",
        CSA_RULES,
    ),
    Mutant(
        "csa-jump-back-seen-not-restarted",
        "CSA jump_back_seen (the time counts from the target's last missed scan)",
        CT,
        "stamp if unseen else t.seen_since,",
        "t.seen_since,",
        CSA_RULES,
    ),
    # ---- the histogram's people of the learning period (background_people)
    Mutant(
        "histogram-people-share-complement",
        "beam histogram people_share (share on people)",
        H,
        "return frequent & (people > 0) & (people >= p.people_share * counts)",
        "return frequent & (people > 0) & (people >= (1.0 - p.people_share) * counts)",
        PEOPLE_BG,
    ),
    Mutant(
        "histogram-guess-nearer-than-person",
        "beam histogram: the wall guessed not nearer than the person",
        H,
        "ok = np.isfinite(t) & (t >= person[need] * w - p.tolerance) & (t < k * w)",
        "ok = np.isfinite(t) & (t < k * w)",
        PEOPLE_BG,
    ),
    Mutant(
        "histogram-relearn-from-person",
        "beam histogram: relearn only beyond the guess",
        H,
        "            self.nearest[beams[people]] = bins[people]\n",
        "",
        PEOPLE_BG,
    ),
    Mutant(
        "histogram-settle-clock-restarts",
        "beam histogram people_settle_seconds (held since first seen)",
        H,
        "start = same & np.isnan(self.settling[beams])",
        "start = same",
        PEOPLE_BG,
    ),
    Mutant(
        "histogram-settle-nearer-leaves",
        "beam histogram settling (a nearer return is no leaving)",
        H,
        "farther = bins > person + reach",
        "farther = np.abs(bins - person) > reach",
        PEOPLE_BG,
    ),
    Mutant(
        "histogram-settle-farther-people-range-leaves",
        "beam histogram settling (a farther range of the people is watched, not left)",
        H,
        "moved = farther & self.people_bins[beams, bins]",
        "moved = np.zeros_like(farther)",
        PEOPLE_BG,
    ),
    Mutant(
        "histogram-settle-farther-people-range-clock-kept",
        "beam histogram settling (the clock starts afresh at a farther range of the people)",
        H,
        "        self.settling[beams[moved]] = stamp\n",
        "",
        PEOPLE_BG,
    ),
    # ---- the MHT listing on plain floats
    Mutant(
        "listing-plain-occluded-deleted-swapped",
        "leg MHT listing costs (occluded, deleted)",
        L,
        "        [-r[OCCLUDED] for r in lps],\n        [-r[DELETED] for r in lps],\n",
        "        [-r[DELETED] for r in lps],\n        [-r[OCCLUDED] for r in lps],\n",
        LISTING,
    ),
    Mutant(
        "listing-plain-scan-first-rates",
        "leg MHT listing costs (the cluster's measurements)",
        MC,
        "            [fal_all[j] for j in js],\n",
        "            fal_all[: len(js)],\n",
        MHT_CORE,
    ),
    Mutant(
        "listing-plain-costs-of-first-scan",
        "leg MHT listing costs (made anew each scan)",
        MC,
        "        self._plain_made = False\n        plain = type(self.branches) is SingleModel",
        "        plain = type(self.branches) is SingleModel",
        MHT_CORE,
    ),
    Mutant(
        "mht-compiled-assembly-refusal-ignored",
        "leg MHT: the compiled assembly's refusal taken for children",
        MC,
        "            if children is not NotImplemented:  # (the children _assemble makes)\n",
        "            if True:  # (the children _assemble makes)\n",
        ("tests/test_track_mht_children_compiled.py",),
    ),
    Mutant(
        "mht-compiled-prune-refusal-ignored",
        "leg MHT: the compiled pruning's refusal taken for hypotheses",
        MC,
        "            if out is not NotImplemented:\n                return out\n"
        "        return prune_children(",
        "            return out\n        return prune_children(",
        ("tests/test_track_mht_children_compiled.py",),
    ),
    Mutant(
        "mht-settled-links-both-single",
        "leg MHT: a link goes when either family's cluster has a single hypothesis",
        MC,
        "            if len(ca.hypotheses) == 1 or len(cb.hypotheses) == 1:\n",
        "            if len(ca.hypotheses) == 1 and len(cb.hypotheses) == 1:\n",
        MHT_STEP,
    ),
    Mutant(
        "mht-settled-links-strict-generation",
        "leg MHT: a link made N scans back is settled",
        MC,
        "            if last <= settled_before and settled(ca) and settled(cb):\n",
        "            if last < settled_before and settled(ca) and settled(cb):\n",
        MHT_STEP,
    ),
    Mutant(
        "mht-link-one-family-skipped",
        "leg MHT: a family and a track born in its gate are linked",
        MC,
        "        if not meas_idx or not fams:  # (families without measurements, or one",
        "        if len(fams) < 2:  # (families without measurements, or one",
        MHT_STEP,
    ),
    Mutant(
        "mht-parents-of-a-part-of-the-cluster",
        "leg MHT: parents of merged clusters (a cluster's own only when it is the whole)",
        MC,
        "            if c.families == fams:  # (the general path below gives its hypotheses)\n",
        "            if c.families <= fams:  # (the general path below gives its hypotheses)\n",
        MHT_STEP,
    ),
    Mutant(
        "mht-best-probability-of-the-last",
        "leg MHT: a family's probability is its cluster's best hypothesis's",
        MC,
        "            p = math.exp(best.log_weight)\n",
        "            p = math.exp(c.hypotheses[-1].log_weight)\n",
        MHT_STEP,
    ),
    Mutant(
        "mht-cluster-families-of-the-best",
        "leg MHT: a cluster's families are those of all its hypotheses",
        MC,
        "                families = frozenset([t.family for t in nodes.values()])\n",
        "                families = frozenset([t.family for t in children[0].tracks])\n",
        MHT_STEP,
    ),
    Mutant(
        "mht-expiry-usual-call-unknown-pairs",
        "leg MHT expiry: odds of pairs not met yet are computed (not taken as existing)",
        "tracking/mht/expiry.py",
        "zip(nodes, keys, strict=True) if table[k] < log_ratio}",
        "zip(nodes, keys, strict=True) if table.get(k, 0.0) < log_ratio}",
        ("tests/test_track_mht_bounds.py",),
    ),
    Mutant(
        "mht-compiled-make-refusal-ignored",
        "leg MHT: the compiled node making's refusal taken for new tracks",
        MC,
        "            if new_nodes is not NotImplemented:\n                return new_nodes\n",
        "            return new_nodes\n",
        ("tests/test_track_mht_children_compiled.py",),
    ),
    # ---- benchmarks/gnn_diagnose.py: the sorting of misses and false positives
    Mutant(
        "gnn-diagnose-before-after-swapped",
        "gnn_diagnose: a miss before the first / after the last match",
        GD,
        'else "before"\n                if k < first[oid]\n                else "after"',
        'else "after"\n                if k < first[oid]\n                else "before"',
        DIAGNOSE,
    ),
    Mutant(
        "gnn-diagnose-switch-from-first-track",
        "gnn_diagnose: id switches from the last matched track",
        GD,
        '                c["id switches"] += 1\n            last[oid] = tid\n',
        '                c["id switches"] += 1\n            last.setdefault(oid, tid)\n',
        DIAGNOSE,
    ),
    # ---- feet-pf on coarse scanners (leg_width) and at the wrong height
    Mutant(
        "feet-leg-beams-ceil",
        "feet-pf leg_width (floor of the beams on a leg)",
        F,
        "beams = max(1, int(np.floor(params.leg_width / spacing)))",
        "beams = max(1, int(np.ceil(params.leg_width / spacing)))",
        FEET_BEAMS,
    ),
    Mutant(
        "feet-segment-link-min",
        "feet-pf leg_width (segment_link at least segment_beams spacings)",
        F,
        "link = max(params.segment_link, params.segment_beams * spacing)",
        "link = min(params.segment_link, params.segment_beams * spacing)",
        FEET_BEAMS,
    ),
    Mutant(
        "feet-still-detector-unscaled",
        "feet-pf leg_width (the still detector's counts scaled too)",
        F,
        "self.still.params = self.unclaimed.params = self.splitter.params = p",
        "self.unclaimed.params = self.splitter.params = p",
        FEET_BEAMS,
    ),
    Mutant(
        "feet-warning-low-lasers",
        "feet-pf warning (lasers at upper-body height)",
        "pipeline/laser_height.py",
        "high = [t for t in topics if t in heights and heights[t] >= UPPER_BODY_MIN_HEIGHT]",
        "high = [t for t in topics if t in heights and heights[t] < UPPER_BODY_MIN_HEIGHT]",
        FEET_HEIGHT,
    ),
    # ---- the group tracker's ids of a split's halves, its N-scan-back and nested presets
    Mutant(
        "groups-halves-farther-kept",
        "group tracker reuse_ids (each id with the nearer half)",
        "tracking/groups/tracker.py",
        "            if swapped < kept:\n",
        "            if swapped > kept:\n",
        HALVES,
    ),
    Mutant(
        "groups-halves-swap-forgotten",
        "group tracker reuse_ids (the swap remembered for later scans)",
        "tracking/groups/tracker.py",
        "                self._ids[keys[a]], self._ids[keys[b]] = ids[a], ids[b]\n",
        "",
        HALVES,
    ),
    Mutant(
        "groups-n-scan-paper-depth",
        "group tracker N-scan-back 3 (8 under --preset paper)",
        "tracking/groups/tracker.py",
        "p.mht.with_defaults(min_ratio=GROUP_MIN_RATIO, n_scan=GROUP_N_SCAN)",
        "p.mht.with_defaults(min_ratio=GROUP_MIN_RATIO)",
        SETTINGS,
    ),
    Mutant(
        "config-nested-table-replaced",
        "configuration: a nested table merged over the preset's key by key",
        "config.py",
        "            out[key] = merged(old, value)\n",
        "            out[key] = value\n",
        SETTINGS,
    ),
    # ---- fit (000's counting of events) and mean shift (004)
    Mutant(
        "fit-ps-pg-swapped",
        "000 Sec. 4.6 (p_S, p_G by counting events)",
        "fitting/groups.py",
        '{"p_c": counts.continued, "p_s": counts.split, "p_g": counts.merged}',
        '{"p_c": counts.continued, "p_s": counts.merged, "p_g": counts.split}',
        FIT,
    ),
    Mutant(
        "fit-clutter-tracks-not-born",
        "000 eq. 14 (a detection of no track: new track, lambda_new, or false alarm)",
        "fitting/legs.py",
        "    counts.new += tally.new\n",
        "    counts.new += 0\n",
        FIT,
    ),
    Mutant(
        "mean-shift-merge-radius",
        "004 Sec. 3 (modes within bandwidth / 2 are one cluster)",
        "clustering/mean_shift.py",
        "return bandwidth / 2.0 if merge_radius is None else merge_radius",
        "return bandwidth / 1.5 if merge_radius is None else merge_radius",
        MEAN_SHIFT,
    ),
    Mutant(
        "csa-count-leg-gap",
        "CSA count_people (within leg_gap of its owner: the other leg)",
        CT,
        "if gap <= p.leg_gap:  # may be an owner's other leg",
        "if gap <= 0.0:  # may be an owner's other leg",
        CSA_RULES,
    ),
    Mutant(
        "csa-count-seconds",
        "CSA count_people (seen for count_seconds near one place)",
        CT,
        "if stamp - since < wait:",
        "if stamp - since < 0.0:",
        CSA_RULES,
    ),
    Mutant(
        "csa-person-groups-single-linkage",
        "CSA person-sized groups by complete linkage",
        CC,
        "d[i] = np.maximum(d[i], d[j])  # complete linkage: the farthest pair",
        "d[i] = np.minimum(d[i], d[j])  # complete linkage: the farthest pair",
        CSA_RULES,
    ),
    Mutant(
        "motion-median-even",
        "sensor-motion check (the median of an even count: mean of the middle two)",
        "pipeline/background.py",
        "return (values[n // 2 - 1] + values[n // 2]) / 2",
        "return values[n // 2]",
        MOTION_MEDIAN,
    ),
    Mutant(
        "segments-many-scan-start",
        "segmentation of a block of scans (every scan's first point starts a segment)",
        "segmentation.py",
        "    is_start[bounds[:-1]] = True  # (every scan's first point; "
        "an empty one's is the next's)\n",
        "",
        SEGMENTS,
    ),
    Mutant(
        "duplicate-scans-any-stamp",
        "scans recorded twice: a scan with the previous one's ranges but another stamp "
        "dropped as a copy",
        "pipeline/duplicate_scans.py",
        "        and a.stamp == b.stamp\n",
        "",
        ("tests/test_hardening_cli.py",),
    ),
    Mutant(
        "duplicate-scans-no-intensities",
        "scans recorded twice: intensities not compared",
        "pipeline/duplicate_scans.py",
        "                and np.array_equal(a.intensities, b.intensities, equal_nan=True)\n",
        "                and True\n",
        ("tests/test_hardening_cli.py",),
    ),
    Mutant(
        "blobs-halfway-from-first",
        "moving blobs (the centre halfway in time a third of the travel from the first)",
        "pipeline/moving_blobs.py",
        "and np.hypot(*(mid - first)) >= self.travel / 3",
        "and np.hypot(*(mid - first)) >= 0.0",
        BLOBS,
    ),
    Mutant(
        "blobs-halfway-from-last",
        "moving blobs (the centre halfway in time a third of the travel from the last)",
        "pipeline/moving_blobs.py",
        "and np.hypot(*(last - mid)) >= self.travel / 3",
        "and np.hypot(*(last - mid)) >= 0.0",
        BLOBS,
    ),
    Mutant(
        "blobs-over-seconds",
        "moving blobs (moved over at least moving_seconds)",
        "pipeline/moving_blobs.py",
        "if t1 - t0 < self.seconds:",
        "if t1 - t0 < 0.0:",
        BLOBS,
    ),
    Mutant(
        "blobs-one-to-one",
        "moving blobs (each previous blob continues at most one)",
        "pipeline/moving_blobs.py",
        "if out[i] is None and j not in used:",
        "if out[i] is None:",
        BLOBS,
    ),
    Mutant(
        "feet-unclaimed-moved",
        "feet-pf births on unclaimed objects (only objects that moved claim_move)",
        "tracking/particle/unclaimed.py",
        "else ok[(stamp - since >= p.claim_time) & moved]",
        "else ok[stamp - since >= p.claim_time]",
        ("tests/test_pf_feet_unclaimed.py",),
    ),
    Mutant(
        "feet-unclaimed-distance",
        "feet-pf births on unclaimed objects (claimed within claim_distance, inclusive)",
        "tracking/particle/unclaimed.py",
        "weights=(d <= distance).astype(np.float64)",
        "weights=(d <= 0.5 * distance).astype(np.float64)",
        ("tests/test_pf_feet_unclaimed.py",),
    ),
    Mutant(
        "csa-person-mixture-sum",
        "Cluster Sorting person_mixture (a person's claim: sum over sqrt of its paths)",
        CV,
        "best = np.argmax(mix / np.sqrt(np.maximum(cnt, 1.0)), axis=0)",
        "best = np.argmax(mix, axis=0)",
        CSA_RULES,
    ),
    Mutant(
        "csa-person-mixture-mean",
        "Cluster Sorting person_mixture (not the mean of a person's paths)",
        CV,
        "best = np.argmax(mix / np.sqrt(np.maximum(cnt, 1.0)), axis=0)",
        "best = np.argmax(mix / np.maximum(cnt, 1.0), axis=0)",
        CSA_RULES,
    ),
    Mutant(
        "csa-person-mixture-unused",
        "Cluster Sorting person_mixture (the Viterbi step uses it)",
        CV,
        "if origin is not None and total.size:",
        "if False:",
        CSA_RULES,
    ),
    Mutant(
        "csa-walked-from-first-pose",
        "Cluster Sorting moving_travel (counted from the first scan of a posed run)",
        CT,
        "self._posed = frame.sensor_pose is not None",
        "self._posed = self._moving",
        CSA_RULES,
    ),
    Mutant(
        "csa-members-unwalked-shown",
        "Cluster Sorting moving_travel (a cluster's people who have not walked are not reported)",
        CT,
        """                if not self._shown_walker(pid):
                    continue
""",
        "",
        CSA_RULES,
    ),
    Mutant(
        "csa-members-walk",
        "Cluster Sorting moving_travel (a cluster's people walk too)",
        CT,
        """                self._walked(m, xy)
                cl.shown[m] = xy""",
        """                cl.shown[m] = xy""",
        CSA_RULES,
    ),
    Mutant(
        "occupancy-holds-disc-edge",
        "occupancy grid (the arrays hold the frame's cells: the far edge checked)",
        "background/occupancy.py",
        "and math.floor((x + radius) / res) + 1 < o0 + h",
        "and math.floor((x + radius) / res) - 3 < o0 + h",
        ("tests/test_background_occupancy.py",),
    ),
    Mutant(
        "occupancy-compiled-casting-always",
        "occupancy grid, compiled learning (first sight only once free space was cast)",
        "background/occupancy.py",
        "                float(p.arrival_window),\n                self.casting,\n",
        "                float(p.arrival_window),\n                True,\n",
        ("tests/test_background_occupancy_compiled.py",),
    ),
    Mutant(
        "occupancy-compiled-live-cells-ignored",
        "occupancy grid, compiled learning (a still laser's live cells seen free at its cast)",
        "background/occupancy.py",
        "(None, None, 0, 0.0) if live is None else live",
        "(None, None, 0, 0.0)",
        ("tests/test_background_occupancy_compiled.py",),
    ),
    Mutant(
        "occupancy-compiled-mark-refusal-ignored",
        "occupancy grid, compiled learning (a refusal of grid_mark left to Python)",
        "background/occupancy.py",
        "            if done is not NotImplemented:\n                return\n",
        "            return\n",
        ("tests/test_background_occupancy_compiled.py",),
    ),
    Mutant(
        "occupancy-compiled-look-increasing-assumed",
        "occupancy grid, a frame looked at in C (beam ids that go back: no still cast)",
        "background/occupancy.py",
        "        return sen, r, reach, increasing\n",
        "        return sen, r, reach, True\n",
        ("tests/test_background_occupancy_compiled.py",),
    ),
    Mutant(
        "occupancy-compiled-look-near-part-kept",
        "occupancy grid, a frame looked at in C (the near returns of ids that went back "
        "are looked at again)",
        "background/occupancy.py",
        "            if not increasing:  # (a part of an increasing run increases too)\n"
        "                increasing = None\n",
        "",
        ("tests/test_background_occupancy_compiled.py",),
    ),
    Mutant(
        "empty-scans-compiled-empty-any-bad",
        "empty scans, counted in C (a scan is empty when no beam is valid, not any)",
        "pipeline/empty_scans.py",
        "        if bad == n:  # (no valid beam)\n",
        "        if bad:  # (no valid beam)\n",
        ("tests/test_empty_scans_compiled.py",),
    ),
    Mutant(
        "still-cast-compiled-this-frames-stamp",
        "still laser's casting, compiled (cells that stop being live get the last frame's stamp)",
        "background/still_cast.py",
        "seen_free, hit, self._safe, self._frame, self._stamp, DIRECTION_TOL",
        "seen_free, hit, self._safe, self._frame, stamp, DIRECTION_TOL",
        ("tests/test_background_occupancy_compiled.py",),
    ),
    Mutant(
        "histogram-compiled-beyond-not-relearned",
        "beam histogram, compiled foreground (a return beyond its static world relearns)",
        H,
        "        if beyond:  # (a return beyond its static world: the Python relearning "
        "follows it)\n            self._relearn(scan)\n",
        "",
        ("tests/test_background_histogram_compiled.py",),
    ),
    Mutant(
        "histogram-compiled-relearning-always",
        "beam histogram, compiled foreground (candidates only where relearning is asked)",
        H,
        "            table.candidate if relearn else None,",
        "            table.candidate,",
        ("tests/test_background_histogram_compiled.py",),
    ),
    Mutant(
        "still-cast-compiled-lost-samples-ignored",
        "still laser's casting, compiled (the old samples of re-listed beams are lost)",
        "background/still_cast.py",
        "lost[0] if lost else None, self._frame",
        "None, self._frame",
        ("tests/test_background_occupancy_compiled.py",),
    ),
    Mutant(
        "histogram-no-beyond-ends-candidates",
        "beam histogram (a scan with no beam beyond its static world ends the candidates)",
        H,
        """            self.candidate[beams] = -1
            return
        cand = self.candidate[beams]""",
        """            return
        cand = self.candidate[beams]""",
        PEOPLE_BG,
    ),
    Mutant(
        "csa-adopted-walk-split",
        "Cluster Sorting moving_travel (a split's new target hands on its own walk)",
        CT,
        """                self._adopted(t.pid, pid, cl.shown.get(pid))
""",
        "",
        CSA_RULES,
    ),
    Mutant(
        "csa-adopted-walk-orphan",
        "Cluster Sorting moving_travel (an orphan's adopter hands on its own walk)",
        CT,
        """                self._adopted(t.pid, m, cl.shown[m])
""",
        "",
        CSA_RULES,
    ),
    Mutant(
        "csa-moving-wall-span",
        "Cluster Sorting moving_wall (the wall continues for the length asked)",
        CC,
        "    return bool(along.max() - along.min() >= length)",
        "    return bool(along.max() - along.min() >= 3.0 * length)",
        CSA_RULES,
    ),
    Mutant(
        "learn-people-every-leg",
        "histogram learning with people (only the legs of the leg MHT's people are people)",
        "pipeline/leg_foreground.py",
        'pos = [t.position for t in tracks.of_kind("leg") if t.track_id in members]',
        'pos = [t.position for t in tracks.of_kind("leg")]',
        LEARN_PEOPLE,
    ),
    Mutant(
        "group-size-pair-arc",
        "000 Sec. 4.6.3 size count (a leg-sized blob covering two legs' arc is a whole person)",
        GO,
        "            pairable &= arc < counting.pair_arc",
        "            pairable &= arc < 2.0 * counting.pair_arc",
        GROUP_SIZE,
    ),
    Mutant(
        "group-size-person-width",
        "000 Sec. 4.6.3 size count (a blob wider than a person holds at least two)",
        GO,
        "across = np.ceil(2.0 * radius[wide] / counting.person_width - 1e-9)",
        "across = np.floor(2.0 * radius[wide] / counting.person_width - 1e-9)",
        GROUP_SIZE,
    ),
    Mutant(
        "group-size-maximum-matching",
        "000 Sec. 4.6.3 size count (one-leg blobs paired by a maximum matching)",
        GO,
        "if (count + 1, -(length + dist[v, u])) > (top[0], -top[1]):",
        "if (count + 1, length + dist[v, u]) > (top[0], top[1]):",
        GROUP_SIZE,
    ),
    Mutant(
        "map-frame-check",
        "--map BAG:/topic (a map in another frame than the poses is refused)",
        "background/bag_map.py",
        "if not grid.frame or not world or grid.frame == world:",
        "if not grid.frame or not world or grid.frame != world:",
        WALKED,
    ),
    Mutant(
        "eval-frame-refusal",
        "evaluate (tracks without a pose against truth in another frame are refused)",
        "evaluation/matching.py",
        "            else:\n                raise EvaluationError(",
        "            elif False:\n                raise EvaluationError(",
        (*EVAL, "tests/test_eval_bruteforce.py"),
    ),
    Mutant(
        "feet-split-keeps-nearer",
        "feet-pf split (the filter keeps the blob nearer its predicted feet midpoint)",
        "tracking/particle/split.py",
        "            k = int(np.argmin(d))",
        "            k = int(np.argmax(d))",
        ("tests/test_pf_feet_split.py",),
    ),
    Mutant(
        "feet-split-time",
        "feet-pf split (two people in one cell for split_time before the split)",
        "tracking/particle/split.py",
        "            if stamp - first < p.split_time:",
        "            if stamp - first < 0.5 * p.split_time:",
        ("tests/test_pf_feet_split.py",),
    ),
    # ---- groups in the shadow of closer returns (000 Sec. 3.3.1 carried over to groups)
    Mutant(
        "group-shadow-margin-side",
        "000 Sec. 3.3.1 for groups (shadowed: the beam ends margin in front)",
        GS,
        "return covered, covered & (ends < dist - margin)",
        "return covered, covered & (ends < dist + margin)",
        SHADOW,
    ),
    Mutant(
        "group-shadow-any-point",
        "000 Sec. 3.3.1 for groups (every contour point in the shadow)",
        GS,
        "return np.logical_and.reduceat(ok & ~seen, starts)",
        "return np.logical_or.reduceat(ok & ~seen, starts)",
        SHADOW,
    ),
    Mutant(
        "group-shadow-other-laser-sees",
        "000 Sec. 3.3.1 for groups (a point another laser sees is not hidden)",
        GS,
        "return np.logical_and.reduceat(ok & ~seen, starts)",
        "return np.logical_and.reduceat(ok, starts)",
        SHADOW,
    ),
    Mutant(
        "group-shadow-beam-floor",
        "000 Sec. 3.3.1 for groups (the beam nearest the point's bearing)",
        GS,
        "beam = np.rint(np.where(bearing < -step / 2, bearing + 2 * math.pi, bearing) / step)",
        "beam = np.floor(np.where(bearing < -step / 2, bearing + 2 * math.pi, bearing) / step)",
        SHADOW,
    ),
    Mutant(
        "group-shadow-hits-strict",
        "000 Sec. 3.3.1 for groups (detected in shadow_hits scans adapts)",
        I,
        "if not must[i] and n.hits >= self._hits]",
        "if not must[i] and n.hits > self._hits]",
        SHADOW,
    ),
    Mutant(
        "group-shadow-hits-age",
        "000 Sec. 3.3.1 for groups (shadow_hits counts detections, not scans)",
        I,
        "if not must[i] and n.hits >= self._hits]",
        "if not must[i] and n.age >= self._hits]",
        SHADOW,
    ),
    Mutant(
        "group-shadow-must-match-adapts",
        "000 Sec. 4.4 (a split or merged track of this scan must be matched)",
        I,
        "if not must[i] and n.hits >= self._hits]",
        "if n.hits >= self._hits]",
        SHADOW,
    ),
    Mutant(
        "group-shadow-at-last-state",
        "000 Sec. 3.3.1 for groups (an older node is tested at its prediction)",
        "tracking/groups/tracker.py",
        "            self.label_model.stamp = frame.stamp\n",
        "",
        (*SHADOW, "tests/test_track_groups.py"),
    ),
    # ---- CSA on a moving laser: moving_window, moving_adopt_near
    Mutant(
        "csa-moving-window-keeps-start",
        "Cluster Sorting moving_window (where travel is measured from moves on)",
        CT,
        """            if window > 0 and self._stamp - since >= window:  # too slow: measure anew
                self._unwalked[pid] = (np.array(xy, dtype=np.float64), self._stamp)""",
        """            if window > 0 and self._stamp - since >= window:  # too slow: measure anew
                self._unwalked[pid] = (start, self._stamp)""",
        CSA_RULES,
    ),
    Mutant(
        "csa-moving-window-no-clock",
        "Cluster Sorting moving_window (the scan's time is the window's clock)",
        CT,
        "        self._stamp = float(stamp)\n",
        "",
        CSA_RULES,
    ),
    Mutant(
        "csa-adopt-near-strict",
        "Cluster Sorting moving_adopt_near (within the distance, inclusive)",
        CT,
        "if person not in self._unwalked and near > 0 and gap <= near:",
        "if person not in self._unwalked and near > 0 and gap < near:",
        CSA_RULES,
    ),
    Mutant(
        "csa-adopt-near-unwalked-too",
        "Cluster Sorting moving_adopt_near (only a person who walked keeps it)",
        CT,
        "if person not in self._unwalked and near > 0 and gap <= near:",
        "if near > 0 and gap <= near:",
        CSA_RULES,
    ),
    Mutant(
        "csa-adopt-near-from-target",
        "Cluster Sorting moving_adopt_near (from where the orphan was last estimated)",
        CT,
        "self._adopted(t.pid, m, cl.shown[m])",
        "self._adopted(t.pid, m, t.mean[:2])",
        CSA_RULES,
    ),
    # ---- torso-shaped runs at torso height (pipeline/torso_blobs.py)
    Mutant(
        "torso-bulge-away",
        "torso runs (the bulge is measured towards the laser)",
        TB,
        "if float((origin - p[0]) @ normal) < 0.0:",
        "if float((origin - p[0]) @ normal) > 0.0:",
        TORSO,
    ),
    Mutant(
        "torso-bulge-either-side",
        "torso runs (a bulge away from the laser is a niche)",
        TB,
        "if float(((p - p[0]) @ normal).max()) >= MIN_BULGE:",
        "if float(np.abs((p - p[0]) @ normal).max()) >= MIN_BULGE:",
        TORSO,
    ),
    Mutant(
        "torso-skip-three",
        "torso runs (three skipped beams cut a run)",
        TB,
        "cuts = np.flatnonzero((step > RUN_GAP) | (skip > 2)) + 1",
        "cuts = np.flatnonzero((step > RUN_GAP) | (skip > 3)) + 1",
        TORSO,
    ),
    Mutant(
        "torso-run-gap-double",
        "torso runs (neighbours farther than RUN_GAP cut a run)",
        TB,
        "cuts = np.flatnonzero((step > RUN_GAP) | (skip > 2)) + 1",
        "cuts = np.flatnonzero((step > 2.0 * RUN_GAP) | (skip > 2)) + 1",
        TORSO,
    ),
    Mutant(
        "torso-sensor-at-origin",
        "torso runs in leg_foreground (the bulge towards the laser's pose)",
        "pipeline/leg_foreground.py",
        "                sensor = np.array([pose.x, pose.y])",
        "                sensor = np.zeros(2)",
        (*TORSO, *LEARN_PEOPLE),
    ),
    # ---- far legs on a moving laser (pipeline/leg_runs.py, [leg_foreground] leg_run_points)
    Mutant(
        "leg-run-width-chord-only",
        "leg runs (a run's width is its chord plus one beam's spacing at its range)",
        LR,
        "width = float(np.hypot(*(p[-1] - p[0]))) + reach * spacing",
        "width = float(np.hypot(*(p[-1] - p[0])))",
        LEG_RUNS,
    ),
    Mutant(
        "leg-run-not-apart",
        "leg runs (a run must stand JUMP in front of the returns beside it)",
        LR,
        "return other is None or bool(ranges[other] - ranges[end] >= JUMP)",
        "return other is None or bool(abs(ranges[other] - ranges[end]) >= 0.0)",
        LEG_RUNS,
    ),
    Mutant(
        "leg-run-skip-two",
        "leg runs (a skipped beam cuts a run)",
        LR,
        "cuts = np.flatnonzero((step > RUN_GAP) | (skip > 1)) + 1",
        "cuts = np.flatnonzero((step > RUN_GAP) | (skip > 2)) + 1",
        LEG_RUNS,
    ),
    Mutant(
        "leg-run-bound-exclusive",
        "far leg blobs (at most max_points run points, inclusive)",
        LR,
        "few = (counts >= 1) & (counts <= max_points)",
        "few = (counts >= 1) & (counts < max_points)",
        LEG_RUNS,
    ),
    Mutant(
        "leg-run-no-bound",
        "far leg blobs (a blob of many run points is not kept)",
        LR,
        "few = (counts >= 1) & (counts <= max_points)",
        "few = counts >= 1",
        LEG_RUNS,
    ),
    Mutant(
        "leg-run-blob-without-run",
        "far leg blobs (a blob must hold a run)",
        LR,
        "few = (counts >= 1) & (counts <= max_points)",
        "few = counts <= max_points",
        LEG_RUNS,
    ),
    Mutant(
        "leg-run-points-only",
        "far leg blobs (the whole blob of a run is kept)",
        LR,
        "return inside & few[np.where(inside, labels, 0)]",
        "return runs & few[np.where(inside, labels, 0)]",
        LEG_RUNS,
    ),
    Mutant(
        "leg-run-every-tracker",
        "far leg blobs in leg_foreground (only for the trackers that need steady points)",
        "pipeline/leg_foreground.py",
        "self.leg_runs = self.params.leg_run_points if steady else 0",
        "self.leg_runs = self.params.leg_run_points",
        LEG_RUNS,
    ),
    # ---- live --frame auto (live/choice.py)
    Mutant(
        "live-choice-sensor-before-pose",
        "live --frame auto (a pose within `within`, inclusive, decides world)",
        LC,
        "        if frame.scans[0].pose is not None:\n",
        "        if frame.scans[0].pose is not None and elapsed < self.within:\n",
        LIVE_FRAME,
    ),
    Mutant(
        "live-choice-within-strict",
        "live --frame auto (sensor once `within` has passed, inclusive)",
        LC,
        "        if elapsed >= self.within:",
        "        if elapsed > self.within:",
        LIVE_FRAME,
    ),
    Mutant(
        "live-choice-restarts-clock",
        "live --frame auto (`within` counts from the first scan)",
        LC,
        "        if self.started is None:\n            self.started = arrival\n",
        "        self.started = arrival\n",
        LIVE_FRAME,
    ),
    Mutant(
        "live-grouping-strictly-newer",
        "live grouping (a frame closes once every other laser sent a scan at least as new)",
        "live/grouping.py",
        'self._newest.get(o, -float("inf")) < ref)',
        'self._newest.get(o, -float("inf")) <= ref)',
        ("tests/test_live_grouping.py",),
    ),
    Mutant(
        "live-grouping-late-joins",
        "live grouping (a scan after its frame left is late and joins no frame)",
        "live/grouping.py",
        "if any(topic in lacking and t <= ref + tol for ref, lacking in self._timed_out):",
        "if False:",
        ("tests/test_live_grouping.py",),
    ),
    Mutant(
        "samples-reservoir-recent",
        "bounded per-frame figures (a uniform sample of the whole run, not of its end)",
        "samples.py",
        "slot = self._rng.randrange(self._count)",
        "slot = self._rng.randrange(self.capacity)",
        ("tests/test_samples.py",),
    ),
    Mutant(
        "npz-truth-frame-mixed",
        "npz recordings (the truth's frame is written only when every frame states the same)",
        "io/npz.py",
        "if len(stated) == 1 and None not in stated:",
        "if len(stated) >= 1 and None not in stated:",
        ("tests/test_npz.py",),
    ),
    Mutant(
        "handover-gate-loose",
        "group ids handed over (a vanished id goes to a group within id_gate of it only)",
        GHO,
        "if d > self.gate:",
        "if d > 2.0 * self.gate:",
        HANDOVER,
    ),
    Mutant(
        "handover-reported-now",
        "group ids handed over (an id reported in this scan is never handed over)",
        GHO,
        "if i not in current and v.stamp < stamp and stamp - v.stamp <= self.memory",
        "if v.stamp < stamp and stamp - v.stamp <= self.memory",
        HANDOVER,
    ),
    Mutant(
        "take-over-gate-loose",
        "a new group takes a coasting group's place only within take_over_distance",
        GT,
        "if d[nearest] <= gate:",
        "if d[nearest] <= 1.5 * gate:",
        HANDOVER,
    ),
    Mutant(
        "coast-last-place",
        "vanished groups reported at their constant-velocity prediction (not their last place)",
        GC,
        "shift = track.velocity * age",
        "shift = 0.0 * track.velocity",
        COAST,
    ),
    Mutant(
        "coast-longer-than-reported",
        "a vanished group is coasted no longer than it had been reported",
        GC,
        "0.0 < age <= min(self.memory, reported_for)",
        "0.0 < age <= self.memory",
        COAST,
    ),
    Mutant(
        "coast-seen-gone-again",
        "a vanished group the scan saw gone is not coasted again",
        GC,
        "del self._last[track_id], self._first[track_id]",
        "self._first[track_id] = self._first[track_id]",
        COAST,
    ),
    Mutant(
        "coast-merged-while-among",
        "a vanished group is coasted beyond coast_time only while among a reported group's "
        "points (merged_coast_time)",
        GC,
        "or among is None or not among(moved))",
        "or among is None)",
        COAST,
    ),
    Mutant(
        "coast-merged-memory",
        "reports are remembered for the longer of coast_time and merged_coast_time",
        GC,
        "return max(self.seconds, self.merged_seconds)",
        "return self.seconds",
        COAST,
    ),
    Mutant(
        "coast-among-blob-distance",
        "a coasted group is among a reported group's points within blob_distance",
        GT,
        "return bool(d2.min() <= reach * reach)",
        "return bool(d2.min() <= 1.3 * reach * reach)",
        COAST,
    ),
    Mutant(
        "seen-past-margin",
        "a place is seen empty only where the beam went more than the margin beyond it",
        GS,
        "return covered & (ends > dist + margin)",
        "return covered & (ends > dist - margin)",
        COAST,
    ),
    Mutant(
        "feet-report-offset-sum",
        "feet-pf report_offset (the mean beam direction of the supporting points, not the sum)",
        F,
        "return offset * total / np.maximum(count, 1)",
        "return offset * total",
        FEET_SURFACE,
    ),
    Mutant(
        "feet-report-offset-once",
        "feet-pf report_offset (a point near both feet of a filter counts once)",
        F,
        "pair = np.unique(point * n_filters + foot // 2)",
        "pair = point * n_filters + foot // 2",
        FEET_SURFACE,
    ),
    Mutant(
        "feet-report-offset-sign",
        "feet-pf report_offset (away from the laser, not towards it)",
        F,
        "return offset * total / np.maximum(count, 1)",
        "return -offset * total / np.maximum(count, 1)",
        FEET_SURFACE,
    ),
    Mutant(
        "surface-three-legs",
        "group size: a continuous surface of exactly three legs' arc is one person",
        GO,
        "        & (legs == 3.0)",
        "        & (legs >= 3.0)",
        ("tests/test_groups_size_resolved.py",),
    ),
    Mutant(
        "surface-gap-loose",
        "group size: a surface whose scan neighbours are at most surface_gap apart",
        GO,
        "        & (gap <= counting.surface_gap)",
        "        & (gap <= 2.0 * counting.surface_gap)",
        ("tests/test_groups_size_resolved.py",),
    ),
    Mutant(
        "size-range-reads-count",
        "group size: the update reads the predicted size within the range of counts",
        GO,
        "    return np.where(fresh, n_hs, np.clip(predicted[:, 4], low, n_range[:, 1]))",
        "    return np.where(fresh, n_hs, np.clip(n_hs, low, n_range[:, 1]))",
        ("tests/test_groups_size_resolved.py",),
    ),
    Mutant(
        "size-range-strides-swapped",
        "group size: the fewest people pair within the far stride, the most within the near",
        GO,
        "    return n_hs, np.column_stack([low, high])",
        "    return n_hs, np.column_stack([high, low])",
        ("tests/test_groups_size_resolved.py",),
    ),
    Mutant(
        "size-range-low-end-standing",
        "group size: only walking groups read down to the count with far strides",
        GO,
        "    low = np.where(walking, n_range[:, 0], n_hs)",
        "    low = np.where(walking, n_hs, n_range[:, 0])",
        ("tests/test_groups_size_resolved.py",),
    ),
    Mutant(
        "size-range-fresh-tracks",
        "group size: a track a split or merge made this scan reads the count",
        GO,
        "    return np.where(fresh, n_hs, np.clip(predicted[:, 4], low, n_range[:, 1]))",
        "    return np.clip(predicted[:, 4], low, n_range[:, 1])",
        ("tests/test_groups_size_resolved.py",),
    ),
    Mutant(
        "torso-no-pairs",
        "group size: at torso height no two blobs are paired as one person's legs",
        GO,
        "pairable = (radius <= counting.leg_radius) & (not counting.torso)",
        "pairable = radius <= counting.leg_radius",
        GROUP_SIZE,
    ),
    Mutant(
        "torso-pairs-setting",
        "group size: torso_pairs keeps the leg pairs at torso height",
        "tracking/groups/tracker.py",
        "torso=torso and not self.params.torso_pairs",
        "torso=torso",
        GROUP_SIZE,
    ),
    Mutant(
        "truth-bag-laser-frame",
        "labels in a bag whose header names the laser's frame are in the sensor frame",
        "io/truth_bag.py",
        "if self.frame_id is None or self.frame_id == self.laser_frame_id:",
        "if self.frame_id is None:",
        TRUTH_BAG,
    ),
    Mutant(
        "feet-handover-reach-grows",
        "feet-pf identity handover (the reach grows with the time since the last report)",
        "tracking/particle/handover.py",
        "reach = self.distance + self.speed * since",
        "reach = self.distance + 0.0 * since",
        ("tests/test_pf_feet_handover.py",),
    ),
    Mutant(
        "feet-handover-shown",
        "feet-pf identity handover (an identity reported in the last scan is not lost)",
        "tracking/particle/handover.py",
        "lost = (since > 0.0) & (since <= self.time) & ~np.isin(self._ids, shown)",
        "lost = (since > 0.0) & (since <= self.time)",
        ("tests/test_pf_feet_handover.py",),
    ),
    Mutant(
        "feet-handover-removes-coasting",
        "feet-pf identity handover (the filter still coasting under the identity is removed)",
        "tracking/particle/feet.py",
        "            gone |= bank.ids == identity",
        "            gone |= False",
        ("tests/test_pf_feet_handover.py",),
    ),
    Mutant(
        "csa-people-among-themselves",
        "csa moving_people: two people of the leg MHT closer than the birth gap start one target",
        "tracking/csa/leg_people.py",
        "        held = np.vstack([held, xy])",
        "        held = held",
        ("tests/test_track_csa.py",),
    ),
    Mutant(
        "csa-people-missed-legs",
        "csa moving_people: a held leg becomes a point only where the foreground has none",
        "tracking/csa/leg_people.py",
        "    return legs[d > gap]",
        "    return legs[d >= 0.0]",
        ("tests/test_track_csa.py",),
    ),
    Mutant(
        "csa-people-hold-window",
        "csa moving_people: the held frames reach back HOLD_SECONDS, both ends kept",
        "tracking/csa/leg_people.py",
        "        while frame.stamp - self._held[0].stamp > self.hold_seconds:",
        "        while frame.stamp - self._held[0].stamp >= self.hold_seconds:",
        ("tests/test_track_csa.py",),
    ),
    Mutant(
        "csa-people-replay",
        "csa moving_people: the held frames are tracked when the laser first moves",
        "tracking/csa/leg_people.py",
        "            self._tracker.update(self._held.popleft())",
        "            self._held.popleft()",
        ("tests/test_track_csa.py",),
    ),
    Mutant(
        "csa-people-watch-from",
        "csa moving_people: the held leg MHT measures the robot's motion from the first pose",
        "tracking/csa/leg_people.py",
        "            self._tracker.watch_from(frame.sensor_pose)",
        "            self._tracker.watch_from(None)",
        ("tests/test_track_csa.py",),
    ),
    Mutant(
        "csa-torso-count-seconds",
        "csa count_people: at torso height people are counted after torso_count_seconds",
        CT,
        "        wait = p.torso_count_seconds if self.at_torso_height else p.count_seconds",
        "        wait = p.count_seconds",
        ("tests/test_track_csa.py",),
    ),
    Mutant(
        "csa-torso-behind-guard",
        "set_laser_height tells the CSA (behind its point guard) whether it is at torso height",
        "pipeline/background.py",
        "            tell(at_torso_height(height))",
        "            tell(False)",
        ("tests/test_pipeline_torso_blobs.py",),
    ),
    Mutant(
        "tracks-moved-unstated-truth",
        "evaluate: truth that states no frame is compared in the tracks' own frame",
        "evaluation/matching.py",
        "if truth.frame is not None and tracks.frame != truth.frame:",
        'if tracks.frame != (truth.frame or "world") and (truth.frame or tracks.sensor_pose):',
        ("tests/test_eval_bruteforce.py",),
    ),
    Mutant(
        "tracks-csv-pose-yaw",
        "tracks CSV: the sensor pose read back as x, y, yaw",
        "io/tracks_csv.py",
        "    return Pose2D(x, y, yaw)",
        "    return Pose2D(y, x, yaw)",
        ("tests/test_io_tracks_csv.py",),
    ),
    Mutant(
        "parquet-frame-metadata",
        "tracks Parquet: the frame read from the file's metadata",
        "batch/parquet.py",
        '    if stated in ("world", "sensor"):',
        "    if False:",
        ("tests/test_batch.py::test_parquet_keeps_the_frame_and_sensor_pose",),
    ),
    Mutant(
        "prelearn-sample-floor",
        "prelearn: a long recording is learned from every ceil(n / prelearn_scans)-th frame",
        "pipeline/prelearn.py",
        "else math.ceil(total / most)",
        "else total // most",
        ("tests/test_pipeline_prelearn.py",),
    ),
    Mutant(
        "prelearn-moving-laser",
        "prelearn: a laser that moves (world frame) is not learned before tracking",
        "pipeline/prelearn.py",
        "            if pose_moved(self._first, frame, self.static.auto_background):",
        "            if False:",
        ("tests/test_pipeline_prelearn.py",),
    ),
    Mutant(
        "prelearn-beyond-nearer",
        "prelearn: the whole recording adds only ranges beyond the learning period's static ones",
        H,
        "        core |= beyond & (np.arange(k)[None, :] > (far + width)[:, None])",
        "        core |= beyond",
        ("tests/test_pipeline_prelearn.py",),
    ),
    Mutant(
        "scan-lines-ctrl-c-leaves-hole",
        "outputs: Ctrl-C between a scan's pages cuts the scan back off",
        "io/scan_lines.py",
        "        except KeyboardInterrupt:  # Ctrl-C between two pages: the file ends with whole "
        "scans\n            if self._seekable:\n                self._undo()\n            raise",
        "        except KeyboardInterrupt:  # Ctrl-C between two pages: the file ends with whole "
        "scans\n            raise",
        ("tests/test_hardening_writers.py",),
    ),
    Mutant(
        "names-token-digit",
        "live: a ROS 2 name part may start with a digit",
        "live/names.py",
        '_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")',
        '_TOKEN = re.compile(r"[A-Za-z0-9_]+")',
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "names-double-underscore",
        "live: a ROS 2 name part may hold '__'",
        "live/names.py",
        '        if "__" in token:',
        '        if "___" in token:',
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "live-output-over-input",
        "live: an --output-prefix may publish on a topic the run reads",
        "cli/live.py",
        "        if _optional_topic(name) is not None and strip_topic(name) in written:",
        "        if False:",
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "detector-used-legs-stage",
        "track: a tracker of legs counts as not using the detector",
        "pipeline/background.py",
        "        isinstance(stage, DetectLegs) or (isinstance(stage, AutoBackground)",
        "        False or (isinstance(stage, AutoBackground)",
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "detector-used-narrowing",
        "track: the foreground narrowed to legs counts as not using the detector",
        "pipeline/background.py",
        "        return self.legs is not None",
        "        return False",
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "features-jumps-by-beam-order",
        "000 features 4, 5: jumps by beam order on a scanner sweeping clockwise",
        "detection/features.py",
        "            out[rows, 3:5] = out[rows, 4:2:-1].copy()\n",
        "",
        ("tests/test_detect_features_compiled.py", "tests/test_hardening_options.py"),
    ),
    Mutant(
        "frame-change-from-scan",
        "bags: a frame_id change is said from the scan after it",
        "io/rosbag.py",
        "FrameChange(first_frame, index)",
        "FrameChange(first_frame, index + 1)",
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "batch-spellings-apart",
        "batch: two spellings of one recording's path are two recordings",
        "cli/batch.py",
        "        spellings.setdefault(path.resolve(), []).append(path)\n",
        "        spellings.setdefault(path, []).append(path)\n",
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "evaluate-shared-truth-of-three",
        "evaluate: one truth of two tracks files is not said",
        "cli/evaluate.py",
        "        if len(names) > 1:",
        "        if len(names) > 2:",
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "pure-python-false-forces",
        "LASERPEOPLE_PURE_PYTHON=false forces the Python listing and features",
        "extensions.py",
        'OFF_VALUES = ("", "0", "false", "no", "off")',
        'OFF_VALUES = ("", "0")',
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "view-empty-tracks-inverted",
        "view: a tracks file with tracks said to hold none",
        "cli/view.py",
        "        if next(iter(rows), None) is None:",
        "        if next(iter(rows), None) is not None:",
        ("tests/test_hardening_new_user.py",),
    ),
    Mutant(
        "view-several-lasers-from-three",
        "view: two lasers and the one drawn not named",
        "cli/view.py",
        "        if len(lasers_here) > 1:",
        "        if len(lasers_here) > 2:",
        ("tests/test_hardening_new_user.py",),
    ),
    Mutant(
        "batch-folder-bag-folders-left-out",
        "batch FOLDER: a ROS 2 bag folder in it is not taken",
        "cli/batch.py",
        '        bag_folder = entry.is_dir() and (entry / "metadata.yaml").is_file()',
        "        bag_folder = False",
        ("tests/test_hardening_new_user.py",),
    ),
    Mutant(
        "not-found-link-never",
        "a link to a missing recording is 'file not found'",
        "io/paths.py",
        "    if not p.is_symlink():",
        "    if True:",
        ("tests/test_hardening_new_user.py",),
    ),
    Mutant(
        "mcap-tail-last-record-dropped",
        "an MCAP cut short: a record ending at the cut is left out",
        "io/mcap_tail.py",
        "            if op == 0 or op >= DATA_END or at + 9 + length > size:",
        "            if op == 0 or op >= DATA_END or at + 9 + length >= size:",
        ("tests/test_hardening_live_record_salvage.py",),
    ),
    Mutant(
        "mcap-tail-records-not-counted",
        "an MCAP cut short: its whole records are not counted (read as holding none)",
        "io/mcap_tail.py",
        "            records += 1\n",
        "",
        ("tests/test_hardening_live_record_salvage.py",),
    ),
    Mutant(
        "record-salvage-not-cut-back",
        "live --record: a failed write's partial bytes stay before the MCAP end records",
        "io/mcap_record.py",
        "            os.ftruncate(self._fd, self.kept_bytes)\n",
        "",
        ("tests/test_hardening_live_record_salvage.py",),
    ),
    Mutant(
        "record-frames-left-in-memory",
        "live --record: frames stay in the chunk buffer (1 MiB) instead of being written out",
        "io/mcap_record.py",
        "        if storage.chunk.bio.tell():\n",
        "        if storage.chunk.bio.tell() > 2**20:\n",
        ("tests/test_hardening_live_record_salvage.py",),
    ),
    Mutant(
        "record-frame-counted-before-written",
        "live --record: the frame the disk refused is counted as held",
        "live/sinks.py",
        'raise self._stopped(exc, f"at frame {self.frames + 1}") from exc',
        "self._writer.frames += 1\n"
        '            raise self._stopped(exc, f"at frame {self.frames}") from exc',
        ("tests/test_hardening_live_record_salvage.py",),
    ),
    Mutant(
        "scan-lines-count-rows-only",
        "track/detect -o on a full disk: scans without rows not counted as held",
        "io/scan_lines.py",
        "        self.scans += 1\n        self.last = scan\n",
        "        self.last = scan\n",
        ("tests/test_hardening_full_disk.py",),
    ),
    Mutant(
        "spelling-underscore-not-dash",
        "names: leg_mht is not leg-mht",
        "spelling.py",
        '    return name.strip().lower().replace("_", "-")',
        "    return name.strip().lower()",
        ("tests/test_hardening_new_user.py",),
    ),
    Mutant(
        "spelling-cutoff-lower",
        "names: suggestions 0.75 alike (p_det -> p_t) are offered",
        "spelling.py",
        "CUTOFF = 0.8\n",
        "CUTOFF = 0.75\n",
        ("tests/test_hardening_new_user.py",),
    ),
    Mutant(
        "config-nested-names-without-table",
        "config: a misspelt nested parameter is offered without its table",
        "config.py",
        '            names.extend(f"{f.name}.{n}" for n in dotted_names(hints[f.name]))\n',
        "            names.extend(dotted_names(hints[f.name]))\n",
        ("tests/test_hardening_new_user.py",),
    ),
    Mutant(
        "live-frame-sensor-takes-poses",
        "live: --world-frame/--mount/--map taken with --frame sensor",
        "cli/live.py",
        '    if frame == "sensor":\n        given = [',
        '    if frame == "world":\n        given = [',
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "map-needs-foreground-model",
        "track: --map refused unless a tracker of points reads the model's foreground",
        "pipeline/recording.py",
        "    if map_path is not None and not static_model_used(preprocess):",
        "    if map_path is not None and background_of(preprocess) is None:",
        ("tests/test_hardening_options.py",),
    ),
    Mutant(
        "train-minimum-inclusive",
        "train: exactly the minimum of legs is enough (a near miss refuses it)",
        "detection/training.py",
        '(others, "non-legs")) if n < minimum]',
        '(others, "non-legs")) if n <= minimum]',
        ("tests/test_hardening_train.py",),
    ),
    Mutant(
        "train-minimum-variants-summed",
        "train --augment: legs counted once as recorded, not once per scanner variant",
        "detection/training.py",
        "return max(int((y > 0).sum()) for y in seen), max(",
        "return sum(int((y > 0).sum()) for y in seen), sum(",
        ("tests/test_hardening_train.py",),
    ),
    Mutant(
        "render-written-in-place",
        "view/track --animate: a picture is written under its own name, not staged beside it",
        "viz/render.py",
        "    target = staging_name(p) if staged else p",
        "    target = p",
        ("tests/test_hardening_pictures.py",),
    ),
    Mutant(
        "error-moved-any-path",
        "an error of the staging file names the output; one of another file keeps its name",
        "errors.py",
        "        if self.path == str(old):",
        "        if self.path is not None:",
        ("tests/test_hardening_pictures.py",),
    ),
    Mutant(
        "ffmpeg-hint-all-words",
        "an ffmpeg refused by the file system is told to free space, not to get libx264",
        "viz/raster.py",
        "    if any(text in err for text in FFMPEG_WRITE_ERRORS):",
        "    if all(text in err for text in FFMPEG_WRITE_ERRORS):",
        ("tests/test_hardening_pictures.py",),
    ),
    Mutant(
        "batch-workers-take-ctrl-c",
        "batch: local workers start with Ctrl-C ignored; this process shuts them down",
        "batch/run.py",
        "    handler = signal.signal(signal.SIGINT, signal.SIG_IGN)",
        "    handler = signal.getsignal(signal.SIGINT)",
        ("tests/test_hardening_batch_interrupt.py",),
    ),
    Mutant(
        "csv-lock-shared",
        "tracks/detections CSV, batch folder: one writer at a time (a shared lock lets two in)",
        "io/paths.py",
        "fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)",
        "fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)",
        ("tests/test_hardening_commands.py", "tests/test_hardening_batch_interrupt.py"),
    ),
    Mutant(
        "csv-taken-not-emptied",
        "tracks/detections CSV: a file taken over is emptied (opened without O_TRUNC)",
        "io/scan_lines.py",
        "                os.ftruncate(self._fh.fileno(), 0)\n",
        "                pass\n",
        ("tests/test_hardening_commands.py",),
    ),
    Mutant(
        "build-one-name-only-str",
        "build/run_batch: a single path where a list is asked for is refused like a string",
        "pipeline/recording.py",
        "    if isinstance(given, str | Path):",
        "    if isinstance(given, str):",
        ("tests/test_hardening_commands.py",),
    ),
    Mutant(
        "live-silence-one-period",
        "live: a laser silent for ten of its scan periods (and 1 s) has stopped",
        "live/source.py",
        "quiet > max(SILENT_MIN, SILENT_PERIODS * period)",
        "quiet > max(SILENT_MIN, period)",
        ("tests/test_hardening_live_silence.py",),
    ),
    Mutant(
        "live-silence-floor-min",
        "live: the 1 s floor of a stop holds for fast lasers",
        "live/source.py",
        "quiet > max(SILENT_MIN, SILENT_PERIODS * period)",
        "quiet > min(SILENT_MIN, SILENT_PERIODS * period)",
        ("tests/test_hardening_live_silence.py",),
    ),
    Mutant(
        "live-silence-period-per-scan",
        "live: the mean scan period is the span over the gaps between scans",
        "live/source.py",
        "/ (n - 1)",
        "/ n",
        ("tests/test_hardening_live_silence.py",),
    ),
    Mutant(
        "evaluate-shift-sign",
        "evaluate: a truth numbered late has stamps before the tracks' of the same number",
        "evaluation/pairing.py",
        "        return -int(k)",
        "        return int(k)",
        ("tests/test_hardening_commands.py",),
    ),
    Mutant(
        "evaluate-shift-no-tolerance",
        "evaluate: only an offset of whole scan periods is a numbering shift",
        "evaluation/pairing.py",
        "abs(periods - k) > SHIFT_TOLERANCE",
        "abs(periods - k) > 0.5",
        ("tests/test_hardening_commands.py",),
    ),
    Mutant(
        "evaluate-shift-span-inclusive",
        "evaluate: a shift is fewer scans than the tracks span",
        "evaluation/pairing.py",
        "abs(k) >= scans",
        "abs(k) > scans",
        ("tests/test_hardening_commands.py",),
    ),
    Mutant(
        "beam-kind-zero-takes-negative",
        "track: a negative range is counted as negative, not as zero",
        "pipeline/empty_scans.py",
        "counts[4] = np.count_nonzero(r == 0.0)",
        "counts[4] = np.count_nonzero(finite & (r <= 0.0))",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "beam-kind-under-min-takes-zero",
        "track: a zero range is counted as zero, not as under range_min",
        "pipeline/empty_scans.py",
        "counts[5] = np.count_nonzero(positive & (r < scan.range_min))",
        "counts[5] = np.count_nonzero(finite & (r >= 0.0) & (r < scan.range_min))",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "truth-names-overlap-integer-ids",
        "evaluate: a named person is numbered after the file's largest integer id",
        "io/truth_csv.py",
        "start = max((i for i in ids if isinstance(i, int)), default=-1) + 1",
        "start = max((i for i in ids if isinstance(i, int)), default=-1)",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "truth-names-sorted",
        "evaluate: names are numbered in the order first seen, not alphabetically",
        "io/truth_csv.py",
        "names = [i for i in dict.fromkeys(ids) if isinstance(i, str)]",
        "names = sorted(i for i in set(ids) if isinstance(i, str))",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "clear-mot-last-pairs-ever",
        "evaluation: CLEAR MOT's last pairs are the last frame's, not every last match",
        "evaluation/clear_mot.py",
        "        self._pairs = {truth_ids[i]: track_ids[j] for i, j in pairs}",
        "        self._pairs.update({truth_ids[i]: track_ids[j] for i, j in pairs})",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "outputs-folder-for-every-option",
        "outputs: only a file output is refused for naming a folder (batch --out is one)",
        "io/paths.py",
        "        if name not in folders and out.is_dir():",
        "        if out.is_dir():",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "config-line-exact-key-only",
        "config: a key set inside an inline table is found on the inline table's line",
        "config.py",
        "            if len(full) <= len(target) and full == target[: len(full)]:",
        "            if full == target:",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "config-line-ignores-table",
        "config: a key is found under its own table, not under another that sets the name",
        "config.py",
        "            full = table + _split_key(key.group(1))",
        "            full = [target[0], *_split_key(key.group(1))]",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "environment-case-blind",
        "environment: a variable is read only under its exact name (case counts)",
        "cli/environment.py",
        "or name in KNOWN:",
        "or name.upper() in KNOWN:",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "staging-left-by-running-run",
        "outputs: only the folder of a process no longer running is said to be left over",
        "io/paths.py",
        "if (m := pattern.fullmatch(e.name)) and e.is_dir() and not _running(int(m.group(1)))",
        "if (m := pattern.fullmatch(e.name)) and e.is_dir()",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "sweep-nested-as-objects",
        "batch --sweep: a grid point is set over the section as a table, nested ones too",
        "batch/options.py",
        "return from_mapping(cls, merged(dataclasses.asdict(obj), values))",
        "return from_mapping(cls, {**{k: getattr(obj, k) for k in obj.__dataclass_fields__}, "
        "**values})",
        ("tests/test_hardening_kinds.py",),
    ),
    Mutant(
        "batch-unused-last-run-decides",
        "batch: an option unused on a recording when none of its runs (lasers) used it",
        "pipeline/unused_options.py",
        "        used[name] = used.get(name, False) or flag",
        "        used[name] = flag",
        ("tests/test_batch_unused.py",),
    ),
    Mutant(
        "batch-unused-failed-judged",
        "batch: failed and empty rows are not counted among the recordings judged",
        "batch/unused.py",
        "        known = row.status != FAILED and row.scans > 0 and flag != UNKNOWN",
        "        known = flag != UNKNOWN",
        ("tests/test_batch_unused.py",),
    ),
    Mutant(
        "fit-worse-error-direction",
        "fit: a learned set whose error rises (clustering error) scores below the defaults",
        "fitting/flow.py",
        "loss = was - now if higher_is_better else now - was",
        "loss = was - now",
        ("tests/test_fit.py",),
    ),
    # ---- the people layer and the leg tracker's glue (issue 35): the same decisions and
    # floats as the arrays they replace
    Mutant(
        "people-width-band-low-only",
        "person tracks: a wide segment's width as numpy's hypot decides it, at both bounds",
        PT,
        "if abs(width - low) <= HYPOT_BAND * width or abs(width - high) <= HYPOT_BAND * width:",
        "if abs(width - low) <= HYPOT_BAND * width:",
        PEOPLE_GLUE,
    ),
    Mutant(
        "people-meas-covs-rows-swapped",
        "person tracks: one leg's and a pair's measurement covariances by row",
        PT,
        "rows = np.array([0 if s == one else 1 for s in stds], dtype=np.intp)",
        "rows = np.array([1 if s == one else 0 for s in stds], dtype=np.intp)",
        PEOPLE_GLUE,
    ),
    Mutant(
        "people-sensor-frame-one-leg",
        "person tracks: no one-leg births in the sensor frame, even when told moving",
        PT,
        "return self.params.one_leg_birth and self.moving and self.world_frame",
        "return self.params.one_leg_birth and self.moving",
        PEOPLE_GLUE,
    ),
    Mutant(
        "legs-log-rates-swapped",
        "leg tracker: log lambda_new, log lambda_fal per measurement (000 Table 10)",
        "tracking/legs.py",
        "        return new[:m], fal[:m]",
        "        return fal[:m], new[:m]",
        PEOPLE_GLUE,
    ),
    Mutant(
        "guard-positive-bound-only",
        "input guard: positions beyond MAX_COORDINATE on either side",
        "tracking/guard.py",
        "clean = bool(np.abs(pos).max(initial=0.0) <= MAX_COORDINATE)",
        "clean = bool(pos.max(initial=0.0) <= MAX_COORDINATE)",
        PEOPLE_GLUE,
    ),
    Mutant(
        "track-drawn-outside-unsaid",
        "track --plot/--animate: track positions outside the picture are said",
        "cli/track.py",
        "    if outside:  # (once",
        "    if not outside:  # (once",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "guard-backward-last-not-first",
        "input guard: the summary names the first scan stamped before the one before",
        "tracking/guard.py",
        "if self.first_backward is None:\n                    self.first_backward = scan_index",
        "if True:\n                    self.first_backward = scan_index",
        ("tests/test_hardening_trackers.py",),
    ),
    Mutant(
        "detect-bound-at-worst",
        "leg detection: the margin's bound takes the deferred stumps at their worst",
        "detection/adaboost.py",
        "values[free] = values[free].max(axis=1, keepdims=True)",
        "values[free] = values[free].min(axis=1, keepdims=True)",
        DEFERRED,
    ),
    Mutant(
        "detect-bound-against-zero",
        "leg detection: the margin's bound compared with 0, not the score threshold",
        "detection/detector.py",
        "return np.asarray(bounds > self.params.score_threshold)",
        "return np.asarray(bounds > 0.0)",
        DEFERRED,
    ),
    Mutant(
        "detect-small-segments-not-completed",
        "leg detection: the deferred features of segments the bound was not asked about",
        "detection/detector.py",
        "            deferred.complete(np.flatnonzero(ok))",
        "            deferred.complete(rows[ok[rows]])",
        DEFERRED,
    ),
    Mutant(
        "sparse-two-beams",
        "sparse legs: taken where a leg gets fewer than two beams, not three",
        "detection/sparse.py",
        "ok = expected_beams(distance, increment, params.leg_width) < MIN_POINTS",
        "ok = expected_beams(distance, increment, params.leg_width) < MIN_POINTS - 1",
        SPARSE,
    ),
    Mutant(
        "sparse-any-depth",
        "sparse legs: a neighbour anywhere behind, not a jump distance behind",
        "detection/sparse.py",
        "ok &= ~seen | (ranges[at] - r >= jump_distance)",
        "ok &= ~seen | (ranges[at] - r >= 0.0)",
        SPARSE,
    ),
    Mutant(
        "sparse-any-width",
        "sparse legs: two points up to twice the leg width apart",
        "detection/sparse.py",
        "ok &= np.hypot(p1[:, 0] - p0[:, 0], p1[:, 1] - p0[:, 1]) <= params.leg_width",
        "ok &= np.hypot(p1[:, 0] - p0[:, 0], p1[:, 1] - p0[:, 1]) <= 2.0 * params.leg_width",
        SPARSE,
    ),
    Mutant(
        "sparse-no-wrap",
        "sparse legs: the neighbour of beam 0 of a full-circle scan taken as no return",
        "detection/sparse.py",
        "beam = np.where(full, beam % n, beam)",
        "beam = np.where(False, beam % n, beam)",
        SPARSE,
    ),
    Mutant(
        "sparse-block-offsets",
        "sparse legs: every scan of a block read from the first scan's ranges",
        "detection/sparse.py",
        "        base, n = starts[owner], counts[owner]",
        "        base, n = 0 * starts[owner], counts[owner]",
        SPARSE,
    ),
    Mutant(
        "sparse-repeated-reading",
        "sparse legs: one reading on two beams counted as two points",
        "detection/sparse.py",
        "ok &= distinct >= params.min_points",
        "ok &= distinct >= 1",
        SPARSE,
    ),
    Mutant(
        "evaluate-stamp-unit-tolerance",
        "evaluate: stamps in ms advance 1000 times as far, within 1 %, not 10 %",
        "evaluation/pairing.py",
        "abs(scale / factor - 1.0) <= UNIT_TOLERANCE",
        "abs(scale / factor - 1.0) <= 0.1",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "evaluate-stamp-unit-tracks-only",
        "evaluate: a truth stamped in ms is named too, not only tracks",
        "evaluation/pairing.py",
        '                (1 / ratio, "truth\'s", "tracks\'"),',
        '                (ratio, "truth\'s", "tracks\'"),',
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "evaluate-position-unit-no-lower-bound",
        "evaluate: positions 320 times as far are not millimetres",
        "evaluation/pairing.py",
        "if 1 / POSITION_UNIT_SPREAD <= scale / factor <= POSITION_UNIT_SPREAD:",
        "if scale / factor <= POSITION_UNIT_SPREAD:",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "evaluate-position-unit-first-scan-only",
        "evaluate: the mean distance is over every paired scan",
        "evaluation/pairing.py",
        "stats.truth_distances = _add_distances(stats.truth_distances, truth.positions)",
        "stats.truth_distances = _add_distances((0.0, 0), truth.positions)",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "csv-rename-any-column-twice",
        "CSV header hint: one column stands for one missing column",
        "io/csv_read.py",
        "            found = by_lower.pop(candidate, None)",
        "            found = by_lower.get(candidate, None)",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "empty-path-text-options",
        "cli: --truth '' and batch '' are refused as empty too",
        "cli/__init__.py",
        "    if (command, param.name) in TEXT_PATH_PARAMETERS:\n        return True\n",
        "",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "bag-other-type-read-as-scans",
        "bags: a laser topic's messages of another type are left out, not damaged scans",
        "io/rosbag.py",
        "            conns = [c for c in conns if c not in others]\n",
        "",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "view-outside-on-both-axes-only",
        "view: a track position outside the area on one axis is outside it",
        "viz/scene.py",
        "off = np.maximum(lo - t, t - hi).max(axis=1)",
        "off = np.maximum(lo - t, t - hi).min(axis=1)",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "live-dropped-warning-any-drop",
        "live: a scan or two dropped is no warning; more than 1 % is",
        "live/source.py",
        "if not n or dropped <= DROPPED_WARN * n:",
        "if not n or not dropped:",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "evaluate-disjoint-no-clock-drift",
        "evaluate: truth of the tracks' clock within 0.5 s + 2 % of the time between",
        "evaluation/pairing.py",
        "<= CLOCK_TOLERANCE + CLOCK_DRIFT * abs(",
        "<= CLOCK_TOLERANCE + 0.0 * abs(",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "evaluate-disjoint-without-clock",
        "evaluate: truth of later scans of the tracks' own clock is all missed, not refused",
        "evaluation/pairing.py",
        "        if self.one_clock():\n            return None\n",
        "",
        ("tests/test_hardening_round7.py",),
    ),
    Mutant(
        "evaluate-disjoint-overlapping-ranges",
        "evaluate: scans that overlap in range are no disjoint truth",
        "evaluation/pairing.py",
        "if tracks_first < 0 or not (tracks_last < truth_first or tracks_first > truth_last):",
        "if tracks_first < 0:",
        ("tests/test_hardening_round7.py",),
    ),
    # --- s35-faithful ---
    # 000 Sec. 2.2, the fourteen features (the Python reference: tests/test_paper_features.py
    # runs it directly, the extension's floats are compared with it elsewhere)
    Mutant(
        "f2-std-divisor-n",
        "000 feature 2 (sigma: divisor n - 1)",
        FT,
        "out[:, 1] = np.sqrt((sxx + syy) / (n - 1.0))",
        "out[:, 1] = np.sqrt((sxx + syy) / n)",
        PAPER_FEATURES,
    ),
    Mutant(
        "f3-lower-median",
        "000 feature 3 (median of an even count: mean of the middle two)",
        FT,
        "med = 0.5 * (vals[:, lo] + vals[:, hi])",
        "med = vals[:, lo] + 0.0 * vals[:, hi]",
        PAPER_FEATURES,
    ),
    Mutant(
        "f3-deviation-from-mean",
        "000 feature 3 (deviation from the vector of medians, not the mean)",
        FT,
        "t2[:, 6] = np.hypot(px - med[0, seg], py - med[1, seg])",
        "t2[:, 6] = np.hypot(dx, dy)",
        PAPER_FEATURES,
    ),
    Mutant(
        "f3-divisor-n-1",
        "000 feature 3 (1/n sum ||x_j - median||)",
        FT,
        "out[:, 2] = sdev / n",
        "out[:, 2] = sdev / (n - 1.0)",
        PAPER_FEATURES,
    ),
    Mutant(
        "f4-f5-jumps-swapped",
        "000 features 4, 5 (jump from the preceding, to the succeeding segment)",
        FT,
        "    out[1:, 3] = gap\n    out[:-1, 4] = gap",
        "    out[1:, 4] = gap\n    out[:-1, 3] = gap",
        PAPER_FEATURES,
    ),
    Mutant(
        "f7-line-largest-residual",
        "000 feature 7 (residual of the best Hessian line)",
        FT,
        "alpha = 0.5 * np.arctan2(-2.0 * sxy, syy - sxx)",
        "alpha = 0.5 * np.arctan2(2.0 * sxy, sxx - syy)",
        PAPER_FEATURES,
    ),
    Mutant(
        "f7-line-mean-residual",
        "000 feature 7 (the residual sum of squares, not its mean)",
        FT,
        "    out[:, 6] = linearity\n",
        "    out[:, 6] = linearity / n\n",
        PAPER_FEATURES,
    ),
    Mutant(
        "f8-circle-absolute-residual",
        "000 feature 8 (sum of squared residuals to the circle)",
        FT,
        "sc = np.add.reduceat(resid * resid, off)",
        "sc = np.add.reduceat(np.abs(resid), off)",
        PAPER_FEATURES,
    ),
    Mutant(
        "f9-radius-sample-moment",
        "000 feature 9 (r_c of x = (A^T A)^-1 A^T b)",
        FT,
        "rc = np.sqrt(xc * xc + yc * yc + sz / n)",
        "rc = np.sqrt(xc * xc + yc * yc + sz / (n - 1.0))",
        PAPER_FEATURES,
    ),
    Mutant(
        "f11-regularity-population-std",
        "000 feature 11 (standard deviation of the steps; sample, documented)",
        FT,
        "out[:, 10] = np.sqrt(ss / (n - 2.0))",
        "out[:, 10] = np.sqrt(ss / (n - 1.0))",
        PAPER_FEATURES,
    ),
    Mutant(
        "f12-curvature-2a",
        "000 feature 12 (k = 4A / (dA dB dC))",
        FT,
        "2.0 * np.abs(cross) / prod, 0.0)",
        "np.abs(cross) / prod, 0.0)",
        PAPER_FEATURES,
    ),
    Mutant(
        "f12-curvature-sum",
        "000 feature 12 (mean curvature; 000 writes a sum, documented)",
        FT,
        "out[:, 11] = s1[:, 1] / n_inner",
        "out[:, 11] = s1[:, 1]",
        PAPER_FEATURES,
    ),
    Mutant(
        "f13-unsigned-angle",
        "000 feature 13 (signed turning angle: convexity/concavity)",
        FT,
        "t1[1:-1, 2] = np.where(mid, np.arctan2(cross, dot), 0.0)",
        "t1[1:-1, 2] = np.where(mid, np.abs(np.arctan2(cross, dot)), 0.0)",
        PAPER_FEATURES,
    ),
    Mutant(
        "f13-mean-over-chords",
        "000 feature 13 (average over the n - 2 angles)",
        FT,
        "out[:, 12] = s1[:, 2] / n_inner",
        "out[:, 12] = s1[:, 2] / (n - 1.0)",
        PAPER_FEATURES,
    ),
    Mutant(
        "f14-speed-over-all-beams",
        "000 feature 14 (averaged over the beams valid in both scans)",
        FT,
        "total / np.maximum(counts, 1.0) / dt",
        "total / n / dt",
        PAPER_FEATURES,
    ),
    Mutant(
        "f14-speed-time-reversed",
        "000 feature 14 (v = (rho_k+1 - rho_k) / (T_k+1 - T_k))",
        FT,
        "dt[seg_at : seg_at + count] = scan.stamp - prev.stamp",
        "dt[seg_at : seg_at + count] = prev.stamp - scan.stamp",
        PAPER_FEATURES,
    ),
    # 000 Table 1 and eq. 1 (AdaBoost with decision stumps)
    Mutant(
        "ab-equal-initial-weights",
        "000 Table 1 (D_1 = 1/(2a), 1/(2b))",
        AB,
        "weights = np.where(pos, 1.0 / (2.0 * a), 1.0 / (2.0 * b))",
        "weights = np.where(pos, 1.0 / (a + b), 1.0 / (a + b))",
        PAPER_ADABOOST,
    ),
    Mutant(
        "ab-alpha-without-half",
        "000 Table 1 (alpha = 1/2 log((1 + r) / (1 - r)))",
        AB,
        "alpha = 0.5 * float(np.log((1.0 + r_c) / (1.0 - r_c)))",
        "alpha = float(np.log((1.0 + r_c) / (1.0 - r_c)))",
        PAPER_ADABOOST,
    ),
    Mutant(
        "ab-update-sign",
        "000 Table 1 step 5 (D exp(-alpha l h))",
        AB,
        "weights = weights * np.exp(-alpha * labels * h)",
        "weights = weights * np.exp(alpha * labels * h)",
        PAPER_ADABOOST,
    ),
    Mutant(
        "ab-no-normalisation",
        "000 Table 1 step 1 (normalise the weights)",
        AB,
        "weights = weights / weights.sum()",
        "weights = weights",
        PAPER_ADABOOST,
    ),
    Mutant(
        "ab-r-halved",
        "000 Table 1 step 3 (r = sum D l h)",
        AB,
        "r_plus = 2.0 * cum - wl.sum()",
        "r_plus = cum - 0.5 * wl.sum()",
        PAPER_ADABOOST,
    ),
    Mutant(
        "ab-polarity-flipped",
        "000 eq. 1 (p: the direction of the inequality)",
        AB,
        "polarity = 1 if r_plus[k, j] >= 0.0 else -1",
        "polarity = -1 if r_plus[k, j] >= 0.0 else 1",
        PAPER_ADABOOST,
    ),
    Mutant(
        "ab-score-ties-plus-side",
        "000 eq. 1 (p f < p theta: a tie is -1)",
        AB,
        'idx = np.searchsorted(th, grid, side="right" if p > 0 else "left")',
        'idx = np.searchsorted(th, grid, side="left" if p > 0 else "right")',
        PAPER_ADABOOST,
    ),
    Mutant(
        "ab-zero-margin-a-leg",
        "000 Table 1 (H = sign(F); F = 0 is not a leg)",
        AB,
        "np.where(self.decision_function(X) > 0.0, 1, -1)",
        "np.where(self.decision_function(X) >= 0.0, 1, -1)",
        PAPER_ADABOOST,
    ),
    # 000 Sec. 3 (eqs. 8-15, Table 10) and Sec. 3.3 (people from leg pairs)
    Mutant(
        "legs-approved-rows-swapped",
        "000 eqs. 9-10 (approved legs take the A column)",
        "tracking/legs.py",
        "rows = [1 if n.family in approved else 0 for n in nodes]",
        "rows = [0 if n.family in approved else 1 for n in nodes]",
        PAPER_LEGS,
    ),
    Mutant(
        "legs-nonadaptive-always-free",
        "000 Sec. 3.4 (non-adaptive with the approved column, Fig. 9)",
        "tracking/legs.py",
        'self._fixed = self._approved if fixed == "approved" else self._free',
        "self._fixed = self._free",
        PAPER_LEGS,
    ),
    Mutant(
        "legs-nonadaptive-still-adapts",
        "000 Sec. 3.4 (non-adaptive: one column for every track)",
        "tracking/legs.py",
        "        if not self.params.adaptive:",
        "        if not self.params.adaptive and not self.approved:",
        PAPER_LEGS,
    ),
    Mutant(
        "legs-lambda-new-is-fal",
        "000 eq. 15 (lambda_new^N_new lambda_fal^N_fal)",
        "tracking/legs.py",
        "self._log_new = float(np.log(params.lambda_new))",
        "self._log_new = float(np.log(params.lambda_fal))",
        PAPER_LEGS,
    ),
    Mutant(
        "mht-lone-occluded-as-deleted",
        "000 eq. 15 (p_occ of an occluded track, one-track cluster)",
        MC,
        "c_occ.append(-float(lp_live[row, OCCLUDED]))",
        "c_occ.append(-float(lp_live[row, DELETED]))",
        PAPER_LEGS,
    ),
    Mutant(
        "mht-matrix-occluded-as-deleted",
        "000 eq. 15 (p_occ of an occluded track, assignment matrix)",
        "tracking/mht/matrix.py",
        "c_occ = -track_label_log_probs[:, OCCLUDED]",
        "c_occ = -track_label_log_probs[:, DELETED]",
        (*PAPER_LEGS, "tests/test_track_mht_probability.py"),
    ),
    Mutant(
        "mht-listing-occluded-as-deleted",
        "000 eq. 15 (p_occ of an occluded track, listed children)",
        L,
        "[-r[OCCLUDED] for r in lps],",
        "[-r[DELETED] for r in lps],",
        PAPER_LEGS,
    ),
    Mutant(
        "people-agreement-absolute",
        "000 Sec. 3.3 (S = sum <theta_i, theta_j>, signed)",
        "tracking/people.py",
        "total += float(ua @ ub)",
        "total += abs(float(ua @ ub))",
        PAPER_LEGS,
    ),
    Mutant(
        "people-window-one-longer",
        "000 Sec. 3.3 (S over the last L steps)",
        "tracking/people.py",
        "while hist.steps and hist.steps[0][0] <= self._step - p.window:",
        "while hist.steps and hist.steps[0][0] < self._step - p.window:",
        PAPER_LEGS,
    ),
    Mutant(
        "people-validate-at-theta-a",
        "000 Sec. 3.3 (validated when S > theta_a)",
        "tracking/people.py",
        "ok = self.agreement(a, b) > p.min_agreement",
        "ok = self.agreement(a, b) >= p.min_agreement",
        PAPER_LEGS,
    ),
    Mutant(
        "people-deleted-after-l-plus-1",
        "000 Sec. 3.3 (deleted after L steps apart)",
        "tracking/people.py",
        "if person.far_steps >= p.window or wide:",
        "if person.far_steps > p.window or wide:",
        PAPER_LEGS,
    ),
    Mutant(
        "people-far-steps-not-consecutive",
        "000 Sec. 3.3 (L consecutive steps apart)",
        "tracking/people.py",
        "person.far_steps = person.far_steps + 1 if d > p.max_leg_distance else 0",
        "person.far_steps = person.far_steps + 1 if d > p.max_leg_distance else person.far_steps",
        PAPER_LEGS,
    ),
    Mutant(
        "people-weights-swapped",
        "000 Sec. 3.3 (multivariate weighted mean of the legs)",
        "tracking/people.py",
        'np.einsum("kij,kj->ki", pb, sol[:, :, 0]) + np.einsum("kij,kj->ki", pa, sol[:, :, 1])',
        'np.einsum("kij,kj->ki", pa, sol[:, :, 0]) + np.einsum("kij,kj->ki", pb, sol[:, :, 1])',
        PAPER_LEGS,
    ),
    # 000 Sec. 2.3.3 (the hand-tuned baseline) and Table 6 (the five best features)
    Mutant(
        "heuristic-min-points-strict",
        "000 Sec. 2.3.3 (fewer than four points are discarded)",
        "detection/heuristic.py",
        "(f[:, 0] >= p.min_points)",
        "(f[:, 0] > p.min_points)",
        PAPER_ADABOOST,
    ),
    Mutant(
        "heuristic-one-jump",
        "000 Sec. 2.3.3 (both jump distances over 30 cm)",
        "detection/heuristic.py",
        "            & (f[:, 4] > p.min_jump)\n",
        "",
        PAPER_ADABOOST,
    ),
    Mutant(
        "heuristic-compactness-by-median",
        "000 Sec. 2.3.3 (standard deviation, feature 2)",
        "detection/heuristic.py",
        "(f[:, 1] < p.max_std)",
        "(f[:, 2] < p.max_std)",
        PAPER_ADABOOST,
    ),
    Mutant(
        "heuristic-motion-by-speed",
        "000 Sec. 2.3.3 (a beam moved more than 2 cm)",
        "detection/heuristic.py",
        "(features.max_beam_motion > p.min_motion)",
        "(np.abs(f[:, 13]) > p.min_motion)",
        PAPER_ADABOOST,
    ),
    Mutant(
        "best-features-smallest-alpha",
        "000 Table 6 (the five stumps of largest weight)",
        "detection/report.py",
        "stumps = sorted(model.classifier.stumps, key=lambda s: -s.alpha)",
        "stumps = sorted(model.classifier.stumps, key=lambda s: s.alpha)",
        PAPER_ADABOOST,
    ),
    # more near misses of 000 Secs. 2-3
    Mutant(
        "people-candidate-within-separation",
        "000 Sec. 3.3 (candidates closer than theta_d = 0.75 m)",
        "tracking/people.py",
        "np.triu(dist < p.max_leg_distance, k=1)",
        "np.triu(dist < p.max_leg_separation, k=1)",
        PAPER_LEGS,
    ),
    Mutant(
        "people-midpoint-covariance",
        "000 Sec. 3.3 (covariance of the weighted mean)",
        "tracking/people.py",
        "covs = pa @ sol[:, :, 2:]",
        "covs = 0.25 * (pa + pb)",
        PAPER_LEGS,
    ),
    Mutant(
        "legs-free-occ-del-swapped",
        "000 Table 10 (p_occ|F 0.63, p_del|F 0.07)",
        "tracking/legs.py",
        "return LabelProbabilities(self.p_det_free, self.p_occ_free, self.p_del_free)",
        "return LabelProbabilities(self.p_det_free, self.p_del_free, self.p_occ_free)",
        PAPER_LEGS,
    ),
    Mutant(
        "labels-log-order",
        "000 eq. 15 (log p_det, p_occ, p_del by label)",
        "tracking/mht/probability.py",
        "return np.log(np.array([self.p_det, self.p_occ, self.p_del]))",
        "return np.log(np.array([self.p_det, self.p_del, self.p_occ]))",
        PAPER_LEGS,
    ),
    Mutant(
        "mht-lone-deleted-as-occluded",
        "000 eq. 15 (p_del of a deleted track, one-track cluster)",
        MC,
        "c_del.append(-float(lp_live[row, DELETED]))",
        "c_del.append(-float(lp_live[row, OCCLUDED]))",
        PAPER_LEGS,
    ),
    Mutant(
        "legs-lambda-fal-is-new",
        "000 eq. 15 (lambda_fal^N_fal)",
        "tracking/legs.py",
        "self._log_fal = float(np.log(params.lambda_fal))",
        "self._log_fal = float(np.log(params.lambda_new))",
        PAPER_LEGS,
    ),
    Mutant(
        "ab-threshold-at-a-value",
        "000 eq. 1 (theta between two training values)",
        AB,
        "np.where(np.arange(n + 1)[:, None] == n, xs[-1:] + 1.0, 0.5 * (below + above))",
        "np.where(np.arange(n + 1)[:, None] == n, xs[-1:] + 1.0, above)",
        PAPER_ADABOOST,
    ),
    Mutant(
        "f12-curvature-wrong-side",
        "000 feature 12 (d_A d_B d_C: the three sides)",
        FT,
        "prod = steps[:-1] * steps[1:] * np.hypot(v1x + v2x, v1y + v2y)",
        "prod = steps[:-1] * steps[1:] * np.hypot(v1x - v2x, v1y - v2y)",
        PAPER_FEATURES,
    ),
    Mutant(
        "f7-line-cross-term-sign",
        "000 feature 7 (residual of the Hessian line)",
        FT,
        "linearity = np.maximum(sxx * ca * ca + 2.0 * sxy * ca * sa + syy * sa * sa, 0.0)",
        "linearity = np.maximum(sxx * ca * ca - 2.0 * sxy * ca * sa + syy * sa * sa, 0.0)",
        PAPER_FEATURES,
    ),
    # 000 Sec. 3.1-3.2 (the leg's Kalman filter and N(z) of eq. 3): the values the
    # extension is given or returns are made in Python
    Mutant(
        "kf-init-velocity-std-as-variance",
        "000 Sec. 3.1 (new tracks: v = 0 with variance sigma_v^2)",
        K,
        "covs[:, 2, 2] = covs[:, 3, 3] = init_velocity_std**2",
        "covs[:, 2, 2] = covs[:, 3, 3] = init_velocity_std",
        PAPER_LEGS,
    ),
    Mutant(
        "kf-loglik-1d-normaliser",
        "000 eq. 3 (N(z; z_hat, S) in 2D: 1 / (2 pi sqrt det S))",
        K,
        "LOG_2PI = float(np.log(2.0 * np.pi))",
        "LOG_2PI = float(0.5 * np.log(2.0 * np.pi))",
        PAPER_LEGS,
    ),
    Mutant(
        "kf-loglik-full-log-det",
        "000 eq. 3 (N(z; z_hat, S): -1/2 log det S)",
        K,
        "    det *= 0.5\n    partial -= det",
        "    partial -= det",
        PAPER_LEGS,
    ),
    # --- s35-harden ---
    Mutant(
        "build-output-over-recording",
        "build(): no output is the recording it reads",
        "pipeline/recording.py",
        "        [recording],\n    )\n",
        "        [],\n    )\n",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "scan-complex-ranges-taken",
        "Scan: ranges of complex numbers are refused, not cut to their real part",
        "scan.py",
        'if array.dtype.kind not in "fiu":',
        'if array.dtype.kind not in "fiuc":',
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "tracks-csv-duplicate-rows-taken",
        "tracks CSV: two rows of one track in one scan are an error naming the lines",
        "io/tracks_csv.py",
        "            if first != line:",
        "            if first != line and False:",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "scan-lines-empty-at-open",
        "tracks CSV: an old file is emptied at the first scan, not at the writer's opening",
        "io/scan_lines.py",
        "if self.created or not self._regular:",
        "if True:",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "manifest-foreign-lines-dropped",
        "batch: foreign manifest lines are kept by the rewrite",
        "batch/manifest.py",
        'text += "".join(line + "\\n" for line in self.foreign)',
        'text += ""',
        ("tests/test_hardening_round8.py",),
    ),
    # --- end s35-harden ---
    # --- s35-reid ---
    Mutant(
        "leg-reid-shared-segment",
        "leg_reid: a segment near two person tracks is nobody's leg",
        "identity/leg_width.py",
        "whole = (count == 1) & (sizes >= p.min_points)",
        "whole = (count >= 1) & (sizes >= p.min_points)",
        ("tests/test_identity_leg_width.py",),
    ),
    Mutant(
        "leg-reid-occluded-after-flipped",
        "leg_reid: a leg whose next beam is nearer is cut (occluded)",
        "identity/leg_width.py",
        "out[:-1] |= adjacent & (rng[after + 1] < rng[after])",
        "out[:-1] |= adjacent & (rng[after + 1] > rng[after])",
        ("tests/test_identity_leg_width.py",),
    ),
    Mutant(
        "leg-reid-never-rewrites",
        "leg_reid: a new id given a dormant identity is reported with it",
        "identity/leg_width.py",
        "                s.output = d.identity\n",
        "                s.output = tid\n",
        ("tests/test_identity_leg_width.py",),
    ),
    Mutant(
        "reidentify-ready-needs-both",
        "reidentify: matched at min_samples widths OR decide_time",
        "tracking/reidentify.py",
        "return signature.count >= p.min_samples or stamp - since >= p.decide_time",
        "return signature.count >= p.min_samples and stamp - since >= p.decide_time",
        ("tests/test_identity_leg_width.py",),
    ),
    Mutant(
        "leg-reid-stage-never-built",
        "leg_reid: the pipeline puts the stage after a tracker that switches it on",
        "pipeline/recording.py",
        'if not getattr(getattr(tracker, "params", None), "leg_reid", False):',
        "if True:",
        ("tests/test_identity_leg_width.py",),
    ),
    # --- s35-speedpf ---
    Mutant(
        "single-linkage-compiled-mask-ignored",
        "000 Sec. 4.1: the compiled single linkage clusters the points the mask leaves out",
        "clustering/single_linkage.py",
        "chosen = None if mask is None else np.ascontiguousarray(mask, dtype=bool)",
        "chosen = None",
        ("tests/test_clustering_compiled.py",),
    ),
    Mutant(
        "kdtree-kept-by-shape",
        "004 Sec. 2.1: a kept KD-tree answers for other points of the same number",
        "clustering/trees.py",
        "key = (pts.shape, pts.tobytes())",
        'key = (pts.shape, b"")',
        ("tests/test_clustering_trees.py",),
    ),
    # --- end s35-speedpf ---
    # --- s35-preset ---
    Mutant(
        "leg-paper-preset-keeps-relinking",
        "000 Sec. 3.3: --preset paper gives a newly validated pair a new id (relink_time 0)",
        "tracking/legs.py",
        '                    "relink_time": 0.0,\n',
        "",
        ("tests/test_paper_leg_preset.py",),
    ),
    Mutant(
        "leg-detector-paper-preset-keeps-offset",
        "000 Sec. 2: --preset paper puts a leg at its segment's centre (centre_offset 0)",
        "detection/detector.py",
        '            "centre_offset": 0.0,\n',
        "",
        ("tests/test_paper_leg_preset.py",),
    ),
    Mutant(
        "leg-foreground-stage-takes-the-paper-leg-mht",
        "--preset paper: the leg foreground stage keeps its own [leg_tracker]",
        "pipeline/background.py",
        "return None if cls is LegTrackerParams else preset",
        "return preset",
        ("tests/test_paper_leg_preset.py",),
    ),
    Mutant(
        "config-infinite-either-sign",
        "configuration: +inf only where the meaning says what inf does",
        "config.py",
        "(infinite and value > 0)",
        "infinite",
        ("tests/test_paper_leg_preset.py",),
    ),
    # --- end s35-preset ---
    # --- s35-harden2 ---
    Mutant(
        "sources-items-unchecked",
        "laser_frames/FrameChooser: an item of the wrong type is named",
        "pipeline/sources.py",
        "            if not isinstance(item, kind):",
        "            if False:",
        (
            "tests/test_hardening_round8.py::"
            "test_sources_given_one_scan_or_the_wrong_items_name_what_they_take",
        ),
    ),
    Mutant(
        "spelling-start-not-suggested",
        "spelling: the start of a known name suggests it",
        "spelling.py",
        "elif len(leaf) >= PREFIX and last.startswith(leaf):",
        "elif False:",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "spelling-starts-in-list-order",
        "spelling: of the names a name starts, the shortest first",
        "spelling.py",
        "scored.append((1.0 + 0.1 * ratio, k))",
        "scored.append((1.0, k))",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "track-ctrl-c-closes-untouched-csv",
        "track: Ctrl-C before the first scan leaves an old tracks CSV as it was",
        "cli/track.py",
        "        pipe.close(failed=exc)  # (as a failed run",
        "        pipe.close()  # (as a failed run",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "scan-float-index-taken",
        "Scan: an index that is no integer is refused",
        "scan.py",
        "        if type(self.index) is not int:  # (one type test",
        "        if False:  # (one type test",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "misspelt-world-frame-unnamed",
        "bags: a world frame no transform names is said to be misspelt, not the mounts",
        "io/rosbag.py",
        "    if world is not None and frames and world not in frames:",
        "    if False:",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "tracks-bag-emptied-before-first-scan",
        "track --bag: a run stopped before its first scan leaves an older bag as it was",
        "pipeline/sinks.py",
        "        if self._writer.frames:\n            self.close()",
        "        if True:\n            self.close()",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "evaluate-recording-as-tracks-unnamed",
        "evaluate: a recording given as TRACKS is named (swapped arguments)",
        "cli/evaluate.py",
        "if given.suffix.lower() in _RECORDINGS_ONLY and not given.is_dir():",
        "if False:",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "topics-string-read-letter-by-letter",
        "recordings: scans(\"/scan\") is refused, not read as the topics '/', 's', ...",
        "io/topics.py",
        "    if isinstance(requested, str | bytes):",
        "    if False:",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "pipeline-of-scans-taken",
        "Pipeline: scans given for frames are refused",
        "pipeline/core.py",
        "                if isinstance(frame, Scan):",
        "                if False:",
        ("tests/test_hardening_round8.py",),
    ),
    Mutant(
        "spelling-swapped-letters-unseen",
        "spelling: a name with two neighbouring letters swapped suggests the name meant",
        "spelling.py",
        "        elif _swapped(leaf, last):",
        "        elif False:",
        ("tests/test_hardening_round8.py",),
    ),
    # --- end s35-harden2 ---
    # --- s36-avoid ---
    Mutant(
        "avoid-share-swapped",
        "sim: the faster of two people steps aside the more",
        "sim/avoidance.py",
        "    share = ((speed[i] + 0.05) / (speed[i] + speed[j] + 0.1))[..., None]",
        "    share = ((speed[j] + 0.05) / (speed[i] + speed[j] + 0.1))[..., None]",
        ("tests/test_sim_avoidance.py",),
    ),
    Mutant(
        "avoid-never-sideways",
        "sim: people passing each other step sideways",
        "sim/avoidance.py",
        "    passing = np.clip(rel_speed / _PASSING, 0.0, 1.0)[..., None]",
        "    passing = np.zeros_like(rel_speed)[..., None]",
        ("tests/test_sim_avoidance.py",),
    ),
    Mutant(
        "avoid-groups-as-strangers",
        "sim: members of one group may stand closer than strangers",
        "sim/avoidance.py",
        "    least = np.where(same, group_distance, distance)",
        "    least = np.where(same, distance, distance)",
        ("tests/test_sim_avoidance.py",),
    ),
    Mutant(
        "random-groups-walk-through",
        "sim: random-groups people step aside for each other",
        "sim/scenarios/random_groups.py",
        "    if p.pass_distance > 0:",
        "    if False:",
        ("tests/test_sim_random_groups.py",),
    ),
    # --- end s36-avoid ---
    # --- s37-first-scan ---
    Mutant(
        "feet-first-scan-never",
        "feet-pf: the objects of the first scan start filters at once",
        "tracking/particle/unclaimed.py",
        "        first = self._stamp is None",
        "        first = False",
        ("tests/test_pf_feet_unclaimed.py",),
    ),
    Mutant(
        "feet-first-scan-always",
        "feet-pf: only the objects of the first scan skip claim_time",
        "tracking/particle/unclaimed.py",
        "        first = self._stamp is None",
        "        first = True",
        ("tests/test_pf_feet_unclaimed.py",),
    ),
    Mutant(
        "feet-merge-always-older-id",
        "feet-pf: two old merging filters keep their own identities",
        "tracking/particle/bank.py",
        "                if keep_identity_age <= 0.0 or young:",
        "                if True:",
        ("tests/test_pf_equations.py", "tests/test_pf_trackers.py"),
    ),
    Mutant(
        "feet-merge-age-of-older",
        "feet-pf: both merging filters must be keep_identity_age old",
        "tracking/particle/bank.py",
        "young = stamp - max(self.born[i], self.born[j]) < keep_identity_age",
        "young = stamp - min(self.born[i], self.born[j]) < keep_identity_age",
        ("tests/test_pf_equations.py",),
    ),
    # --- end s37-first-scan ---
    # --- s38-recording-map ---
    Mutant(
        "map-share-of-hits-only",
        "map of a moving robot's recording: the share counts the frames that saw a cell free",
        "background/recording_map.py",
        "(hits >= rule.hit_share * (hits + self._free))",
        "(hits >= rule.hit_share * hits)",
        ("tests/test_background_recording_map.py",),
    ),
    Mutant(
        "map-min-hits-dropped",
        "map of a moving robot's recording: a static cell needs min_hits returns",
        "background/recording_map.py",
        "(self._hits >= rule.min_hits)",
        "(self._hits >= 1)",
        ("tests/test_background_recording_map.py",),
    ),
    Mutant(
        "map-hit-and-pass-free",
        "map of a moving robot's recording: a cell hit and passed in one frame is hit",
        "background/recording_map.py",
        "        seen[near_flat[marked[near_flat] == self.frames]] -= 1",
        "        seen[near_flat[marked[near_flat] == self.frames]] -= 0",
        ("tests/test_background_recording_map.py",),
    ),
    Mutant(
        "map-rows-not-flipped",
        "map of a moving robot's recording: image rows run from the largest y down",
        "background/recording_map.py",
        "occupied = np.ascontiguousarray(static.T[::-1])",
        "occupied = np.ascontiguousarray(static.T)",
        ("tests/test_background_recording_map.py",),
    ),
    Mutant(
        "map-not-seeded",
        "map of a moving robot's recording seeds the occupancy grid",
        "pipeline/background.py",
        "occupancy_model(self.map_path, self.static.occupancy, self.recording_map)",
        "occupancy_model(self.map_path, self.static.occupancy, None)",
        ("tests/test_pipeline_prelearn.py",),
    ),
    Mutant(
        "prior-dilated-rows-only",
        "a prior map dilated once to the grid's reach: rows and columns",
        "background/occupancy.py",
        "            out[:, dc : dc + w] |= rows[:, radius : radius + w]",
        "            out[:, dc : dc + w] |= rows[:, radius : radius + w] & False",
        ("tests/test_background_occupancy.py",),
    ),
    Mutant(
        "prior-dilated-origin-unrotated",
        "a prior map dilated once: its padded corner moves back along the map's own axes",
        "background/occupancy.py",
        "origin = (x0 - shift * (c - s), y0 - shift * (s + c), yaw)",
        "origin = (x0 - shift * (c + s), y0 - shift * (s + c), yaw)",
        ("tests/test_background_occupancy.py",),
    ),
    # --- end s38-recording-map ---
    # --- s39-group-truth-and-map-reach ---
    Mutant(
        "group-tracks-scored-against-people",
        "evaluate with kind group scores the truth's groups, not its people",
        "evaluation/report.py",
        "        truth_frames = map(group_truth, truth_frames)\n",
        "        truth_frames = iter(truth_frames)\n",
        ("tests/test_evaluation_group_truth.py",),
    ),
    Mutant(
        "group-truth-frame-dropped",
        "the groups' truth keeps the coordinate frame of the people's",
        "evaluation/group_truth.py",
        "ids, pos, frame=frame.frame)",
        "ids, pos)",
        ("tests/test_evaluation_group_truth.py",),
    ),
    Mutant(
        "group-truth-at-first-member",
        "a true group is at the mean of its members' positions",
        "evaluation/group_truth.py",
        "frame.positions[np.isin(frame.person_ids, people)].mean(axis=0)",
        "frame.positions[np.isin(frame.person_ids, people)][0]",
        ("tests/test_evaluation_group_truth.py",),
    ),
    Mutant(
        "map-hit-reach-ignored",
        "map of a moving robot's recording: beams near a return of their frame see nothing",
        "background/recording_map.py",
        "        self._reach = self.rule.reach_offsets()",
        "        self._reach = np.zeros((1, 2), dtype=np.int64)",
        ("tests/test_background_recording_map.py",),
    ),
    Mutant(
        "map-hit-reach-square",
        "map of a moving robot's recording: the reach is a disc of cells",
        "background/recording_map.py",
        "        keep = di * di + dj * dj <= k * k",
        "        keep = np.abs(di) + np.abs(dj) >= 0",
        ("tests/test_background_recording_map.py",),
    ),
    # --- end s39-group-truth-and-map-reach ---
)


@dataclass(frozen=True)
class Outcome:
    """What one run gave: "killed", "survived", "stale" or "error", and its seconds."""

    name: str
    result: str
    seconds: float
    detail: str = ""


def _copy_tree(dest: Path) -> Path:
    """A copy of the repository's src/, tests/, benchmarks/ and pyproject.toml under ``dest/repo``
    (no ``shared`` beside it, so tests needing the real recordings skip)."""
    repo = dest / "repo"
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", ".mypy_cache", ".ruff_cache")
    shutil.copytree(REPO / "src", repo / "src", ignore=ignore)
    shutil.copytree(REPO / "tests", repo / "tests", ignore=ignore)
    shutil.copytree(REPO / "benchmarks", repo / "benchmarks", ignore=ignore)  # tests use some
    shutil.copy2(REPO / "pyproject.toml", repo / "pyproject.toml")
    return repo


def _run_tests(repo: Path, tests: tuple[str, ...]) -> tuple[int, str]:
    """pytest on ``tests`` (those that exist) in ``repo``, one file after the other until
    one fails (so a killed mutant costs the collection of its first failing file only):
    (return code, last line of the output)."""
    here = [t for t in tests if (repo / t.split("::")[0]).exists()]
    if not here:
        return 5, "none of its test files exist"
    env = {k: v for k, v in os.environ.items() if k != "LASERPEOPLE_SHARED_DATA"}
    env["PYTHONPATH"] = str(repo / "src")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    tail = ""
    for test in here:
        # -n 0: one process (the addopts' xdist would end a run stopped by -x with exit 2)
        cmd = [
            sys.executable,
            "-m",
            "pytest",
            "-x",
            "-q",
            "-n",
            "0",
            "-p",
            "no:cacheprovider",
            test,
        ]
        try:
            done = subprocess.run(
                cmd, cwd=repo, env=env, capture_output=True, text=True, timeout=TIMEOUT
            )
        except subprocess.TimeoutExpired:
            return -1, f"{test} timed out after {TIMEOUT:.0f} s"
        tail = f"{test}: " + (done.stdout.strip().splitlines() or [""])[-1]
        if done.returncode not in (0, 5):  # 5: no test collected (all skipped is 0)
            return done.returncode, tail
    return 0, tail


def run_mutant(m: Mutant) -> Outcome:
    """Apply ``m`` to a fresh copy and run its tests."""
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix=f"mutant-{m.name}-") as tmp:
        repo = _copy_tree(Path(tmp))
        path = repo / "src" / "laserpeople" / m.path
        text = path.read_text()
        count = text.count(m.original)
        if count != 1:
            return Outcome(m.name, "stale", 0.0, f"snippet found {count} times in {m.path}")
        path.write_text(text.replace(m.original, m.replacement))
        code, tail = _run_tests(repo, m.tests)
    seconds = time.perf_counter() - start
    if code == 0:
        return Outcome(m.name, "survived", seconds, tail)
    if code == -1:
        return Outcome(m.name, "killed", seconds, f"(tests timed out) {tail}")
    if code == 1:
        return Outcome(m.name, "killed", seconds, tail)
    return Outcome(m.name, "error", seconds, f"pytest exit {code}: {tail}")


def baseline(tests: tuple[str, ...]) -> tuple[int, str]:
    """The tests of every selected mutant on the unmutated copy."""
    with tempfile.TemporaryDirectory(prefix="mutant-baseline-") as tmp:
        return _run_tests(_copy_tree(Path(tmp)), tests)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--jobs", type=int, default=1, help="mutants run at once")
    ap.add_argument("--only", nargs="+", default=None, help="mutant names to run")
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument("--no-baseline", action="store_true", help="skip the unmutated run")
    args = ap.parse_args(argv)
    chosen = [m for m in MUTANTS if args.only is None or m.name in args.only]
    if args.only is not None:
        unknown = set(args.only) - {m.name for m in MUTANTS}
        if unknown:
            ap.error(f"unknown mutant(s): {', '.join(sorted(unknown))} (see --list)")
    if args.list:
        stale = 0
        for m in chosen:
            found = (REPO / "src" / "laserpeople" / m.path).read_text().count(m.original)
            note = "" if found == 1 else f"  STALE (snippet found {found} times)"
            stale += found != 1
            print(f"{m.name:34s} {m.paper:50s} {m.path}{note}")
        print(f"{len(chosen)} mutants, {stale} stale")
        return 1 if stale else 0
    if not args.no_baseline:
        tests = tuple(sorted({t for m in chosen for t in m.tests}))
        code, tail = baseline(tests)
        print(f"baseline (unmutated): pytest exit {code}: {tail}", flush=True)
        if code != 0:
            print("the tests fail without a mutant: fix them first", file=sys.stderr)
            return 2

    def run_and_say(m: Mutant) -> Outcome:
        o = run_mutant(m)
        print(f"  {o.name}: {o.result} ({o.seconds:.0f} s) {o.detail}", flush=True)
        return o

    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        outcomes = list(pool.map(run_and_say, chosen))
    width = max(len(m.name) for m in chosen)
    print(f"{'mutant':{width}s}  {'paper':46s}  {'result':8s}  {'s':>6s}")
    for m, o in zip(chosen, outcomes, strict=True):
        print(f"{m.name:{width}s}  {m.paper[:46]:46s}  {o.result:8s}  {o.seconds:6.1f}")
    for o in outcomes:
        if o.result in ("stale", "error"):
            print(f"  {o.name}: {o.detail}")
    counts = {r: sum(o.result == r for o in outcomes) for r in ("killed", "survived")}
    others = len(outcomes) - counts["killed"] - counts["survived"]
    print(
        f"{counts['killed']} killed, {counts['survived']} survived, {others} stale or error "
        f"of {len(outcomes)} mutants"
    )
    return 0 if counts["killed"] == len(outcomes) else 1


if __name__ == "__main__":
    raise SystemExit(main())
