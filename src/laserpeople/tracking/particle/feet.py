"""The feet tracker of 004 Sec. 2.1 (after Shao et al. 2008): one particle filter per person
at feet height with a walking model.

- Detection (Fig. 1): the feet of a walking person form two clusters, merge into one while
  the moving foot passes the standing one, and split again. Mean-shift clusters of two
  consecutive scans are compared by their overlap (a point of the new scan within
  ``overlap_distance`` of a point of the old one links the two clusters): one new cluster
  linked to two old ones is a *merge*, one old cluster linked to two new ones a *split*.
  A split within ``sequence_time`` and ``sequence_distance`` of a merge completes the
  sequence and starts a filter at the two split clusters.
- State (eqs. 1-2): feet (x_l, y_l, x_r, y_r) [m], stride s [m], period T [s], phase gamma
  [rad], direction alpha [rad]; in each half period one foot moves along alpha by
  s |cos gamma_t - cos gamma_{t-1}|, plus Gaussian diffusion of every parameter.
- Weight (eqs. 3-7): o_l and o_r sum Gaussian kernels (sigma ``delta``) of the foreground
  points around each foot, floored at P_0; o_b scores the feet's separation along alpha
  against -s cos gamma with tolerance h; w = o_l o_r o_b.
- Repelling term: each particle's weight is multiplied by prod_g (1 - exp(-|c - c_g|^2 /
  (2 sigma_r^2))) over the other filters g, with c the particle's feet midpoint and c_g
  filter g's estimate, so that two filters do not collapse onto one person.
- Death: no foreground point near the feet for ``miss_time``, or a filter within
  ``merge_distance`` of an older one. A departure from 004: of two merging filters the
  one with the better smoothed likelihood survives, under the older identity, but two
  filters both ``keep_identity_age`` old keep their own (two people who cross).
- A departure from 004: points of an object too big for a person's feet (a baggage cart;
  ``max_eigenvalue`` over single-linkage objects, as in the upper-body tracker) are
  dropped before anything else: they start no filter, weigh none and support none.
- A departure from 004 for people close together (``voronoi``; False restores 004): a
  point weighs only the filter with the nearest estimated foot (the feet's Voronoi cells,
  as the upper-body tracker's eq. 9 uses the filters' cells) instead of every filter
  within ``gate``, so that a filter's particles are not drawn onto the legs of a person
  walking beside it.
- A departure from 004: o_b also scores the feet's sideways distance against a step width
  (``step_width``, tolerance ``h_width``; 0 switches it off), so that both feet cannot
  settle on one object (a suitcase, one leg).
- Departures from 004 for accessories, by the shape of the surface segments the points
  form (single linkage at ``segment_link``; leg-shaped: largest covariance eigenvalue at
  most ``leg_eigenvalue``): a point on a segment longer than a leg (a suitcase's face, a
  skirt's side) weighs ``long_weight`` in eqs. 3-4, so that feet settle on legs rather
  than on a carried suitcase; leg-shaped segments of an object too big for a person
  still weigh and support filters (``rescue_legs``: the foot of a person pushing a cart
  touches it); and a filter on a blob without legs (a long skirt hides them) reports the
  blob's centre instead of the walking model's body position (``blob_body``).
- A departure from 004 for people who stop and walk on (``cell_refresh``; 0 restores
  004): a filter whose Voronoi cell's points are centred farther than ``cell_refresh`` from
  its feet midpoint restarts a share of its particles from those points, split in two
  along their major axis, as from a detected step (a filter that stood with its person
  has strides near 0 and stays behind when the person walks off, and at a low scan rate
  no step is detected to refresh it).
- A departure from 004 for people in parties (``claim_distance``; 0 restores 004): an
  object of a leg's size or more and a person's size at most, with no filter's estimated
  foot within ``claim_distance``, that stays so for ``claim_time`` starts a filter
  (:mod:`~laserpeople.tracking.particle.unclaimed`): a person walking abreast of others
  often shows one leg behind the other and no merge -> split of their own. The objects
  of the first scan start filters at once (``first_scan_births``): the people in view
  when tracking starts.
- A departure from 004 for a filter standing on two people (``split_distance``; 0
  restores 004): a filter whose Voronoi cell holds two blobs of a leg's or a person's
  size, more than ``split_distance`` apart, for ``split_time`` keeps the one nearer its
  predicted feet midpoint and a filter starts on the other
  (:mod:`~laserpeople.tracking.particle.split`).
- A departure from 004 for people found again (``handover_time``; 0 restores 004): a new
  filter that starts near where a track stopped being reported, soon after, takes over
  that track's identity (:mod:`~laserpeople.tracking.particle.handover`), and a filter
  still coasting under it is removed.
- A departure from 004 for coarse scanners (``leg_width``; 0 restores the counts as set):
  the point counts that tell a leg or a standing person (``blob_leg_points``,
  ``still_points``) are capped at what the laser shows of a leg at the range of the scan's
  foreground (``leg_width`` over the beam spacing), and ``segment_link`` spans at least
  ``segment_beams`` beam spacings, so that a 1 deg scanner's one or two points per leg
  still make legs (:func:`scaled_to_beams`).

The reported person position is the weighted mean of the body positions the walking model
implies (the feet midpoint moved by :func:`body_offset`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import cluster_covariances, mean_shift, single_linkage
from laserpeople.clustering.links import cluster_links
from laserpeople.clustering.trees import close_pairs, kdtree, nearest
from laserpeople.config import param
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame, FrameField
from laserpeople.lazy_scipy import cKDTree
from laserpeople.tracking.particle.bank import FilterBank
from laserpeople.tracking.particle.frames import beam_directions
from laserpeople.tracking.particle.handover import LostIdentities
from laserpeople.tracking.particle.objects import (
    ObjectMemory,
    kept_labels,
    largest_eigenvalue,
    object_eigenvalues,
    small_objects,
    two_feet,
)
from laserpeople.tracking.particle.split import PartySplitter, Split
from laserpeople.tracking.particle.unclaimed import UnclaimedDetector
from laserpeople.tracking.particle.upper_body import gather_cells, voronoi_cells
from laserpeople.tracks import Tracks

XL, YL, XR, YR, S, T, GAMMA, ALPHA = range(8)
TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class FeetParams:
    """Parameters of the feet particle-filter tracker (004 Sec. 2.1, Shao et al. 2008)."""

    config_section = "feet_pf"
    paper_preset = MappingProxyType(
        {  # 004 where the defaults depart from it (docs/papers.md)
            "h_width": 0.0,
            "voronoi": False,
            "max_eigenvalue": 0.0,
            "long_weight": 1.0,
            "rescue_legs": False,
            "blob_body": False,
            "overlap_max": 0.0,
            "still_time": 0.0,
            "cell_refresh": 0.0,
            "leg_width": 0.0,
            "claim_distance": 0.0,
            "first_scan_births": False,
            "keep_identity_age": 0.0,
            "split_distance": 0.0,
            "report_offset": 0.0,
            "handover_time": 0.0,
            "leg_reid": False,
        }
    )

    particles: int = param(
        500,
        "assumption: 500 particles per filter meets the speed target (docs/schenk-tables.md)",
        "particles per filter",
    )
    delta: float = param(
        0.06, "assumed (Shao et al.'s value not in 004)", "sigma of the foot kernels, eqs. 3-4", "m"
    )
    p0: float = param(0.02, "assumed; tuned with miss_time", "P_0, floor of o_l and o_r (eqs. 3-4)")
    h: float = param(0.12, "assumed", "h of eq. 6 (tolerance of the feet separation)", "m")
    step_width: float = param(
        0.2,
        "assumed: about the hip width (not in 004)",
        "sideways distance between the feet across the walking direction",
        "m",
    )
    h_width: float = param(
        0.06,
        "departure from 004, which scores the feet's distance only along the walking "
        "direction (eq. 6; 0 here); measured on seeds 0-1 of 7 scenes: MOTP 0.69 at 0, "
        "0.77 at 0.06 (docs/schenk-tables.md)",
        "tolerance of the sideways distance between the feet (0: not scored)",
        "m",
    )
    bandwidth: float = param(
        0.2,
        "assumed: merges feet passing 0.2 m apart, splits them at a step's length",
        "mean-shift bandwidth for detection",
        "m",
    )
    overlap_distance: float = param(
        0.25,
        "assumed; a running foot (~5 m/s) moves 0.1 m between scans at 50 Hz and leaves "
        "the cluster it merged with in one scan, so 0.12 m missed running steps; measured "
        "on seeds 6-7 of 'fast': MOTP 0.67 at 0.12, 0.86 at 0.25",
        "points of consecutive scans this close link their clusters (at 50 Hz; scaled "
        "up with the time between scans)",
        "m",
    )
    overlap_max: float = param(
        0.5,
        "departure from 004 (0 here: no bound; 004 scans at 50 Hz, where the link "
        "distance is 0.25 m either way); scaled to a 15 Hz scanner the link distance "
        "reached 0.83 m and linked two people standing 0.9 m apart (legs 0.56 m apart), "
        "whose clusters then merged and split every scan and started filters between "
        "them; feet-crossing and feet-office, seeds 0, 3: MOTP 0.55 at 0.5, 0.55 at 0.4; "
        "carry case at 25 Hz, seed 5: 0.80 at 0.5, 0.67 at 0.4 (docs/schenk-tables.md)",
        "largest link distance after scaling ``overlap_distance`` with the time between "
        "scans (0: no bound)",
        "m",
    )
    still_time: float = param(
        1.0,
        "departure from 004 (0 here: only a step sequence starts a filter); a person who "
        "stood still once their filter was lost (hidden by a passer-by for longer than "
        "``miss_time``) was never found again (docs/schenk-tables.md)",
        "a person-sized object (single linkage at ``link_distance``, at least "
        "``still_points`` points, largest covariance eigenvalue at most "
        "``still_eigenvalue``) whose centre stays within ``still_move`` this long, with no "
        "filter within ``birth_exclusion``, starts a filter; 0 disables",
        "s",
    )
    still_move: float = param(
        0.1,
        "assumed: a standing person sways a few cm; a walker moves 0.4 m or more per second",
        "farthest a still object's centre may move from where it was first seen",
        "m",
    )
    still_points: int = param(
        4, "assumed: two legs of 2 points each", "fewest points of a still object"
    )
    still_eigenvalue: float = param(
        0.015,
        "assumed: two legs side by side span at most ~0.4 m (a uniform 0.4 m spread has 0.013)",
        "largest covariance eigenvalue of a still object",
        "m^2",
    )
    claim_distance: float = param(
        0.3,
        "departure from 004 (0 here: only a step sequence or a still object starts a "
        "filter); in parties walking abreast 0.75 m apart a person shows one leg behind "
        "the other and their steps refresh a neighbour's filter, so a party got fewer "
        "filters than people; random-groups tuning seeds 0-19 at feet height: MOTP 0.501 "
        "at 0, 0.521 at 0.3 (seven of them: 3.62 summed at 0.3, 3.58 at 0.4; "
        "docs/schenk-tables.md)",
        "an object (single linkage at ``link_distance``) of at least ``blob_leg_points`` "
        "points and a largest covariance eigenvalue of at most ``still_eigenvalue`` with "
        "no point this close to a filter's estimated foot is unclaimed; one unclaimed for "
        "``claim_time`` starts a filter "
        "(:mod:`~laserpeople.tracking.particle.unclaimed`); 0 disables",
        "m",
    )
    claim_time: float = param(
        0.5,
        "assumed: half a step period, longer than a swinging foot is ahead of its filter; "
        "seven random-groups tuning seeds: MOTP 3.62 summed at 0.5, 3.53 at 1",
        "how long an object must stay unclaimed (``claim_distance``) to start a filter",
        "s",
    )
    claim_speed: float = param(
        2.0,
        "assumed: faster than people walk (random-groups 0.5-1.5 m/s)",
        "an unclaimed object is the previous scan's nearest one within this speed times "
        "the time between the scans",
        "m/s",
    )
    claim_move: float = param(
        0.25,
        "assumed: half a second of the slowest walk (0.5 m/s); without it clutter in a "
        "moving robot's foreground started filters (random-groups tuning seeds 0-19: MOTP "
        "0.517 at 0, 0.521 at 0.25; seed 12 0.423 and 0.481)",
        "an unclaimed object (``claim_distance``) starts a filter only once its centre "
        "moved this far from where it was first seen",
        "m",
    )
    first_scan_births: bool = param(
        True,
        "departure from 004 (false here: the people in view when tracking starts wait for "
        "a step, ``still_time`` or ``claim_time``); 004's Tables 1-3 on their held-back "
        "seeds: MOTP 0.92, 0.95, 0.94 -> 0.94, 0.98, 0.97; random-groups at feet height, "
        "three draws: tuning +0.008, held back unchanged (docs/schenk-tables.md)",
        "with ``claim_distance`` > 0, every object of the tracker's first scan that the "
        "unclaimed detector takes for a person (a leg's size or more, a person's at most) "
        "starts a filter at once: there is nothing yet to tell walkers from clutter by, "
        "and what stands still the static world model has removed",
    )
    sequence_time: float = param(1.0, "assumed", "longest merge-to-split time", "s")
    sequence_distance: float = param(
        0.5, "assumed", "largest distance between a merge and its split", "m"
    )
    gate: float = param(
        0.7, "assumed", "points farther than this from a filter's feet are not used", "m"
    )
    sigma_repel: float = param(0.2, "assumed", "range of the repelling term", "m")
    voronoi: bool = param(
        True,
        "departure from 004 (False here: every point within ``gate`` weighs every filter "
        "and the repelling term alone keeps them apart); two people walking side by side "
        "0.6 m apart drew one filter onto both and the other died (join, seeds 200-203: "
        "MOTP 0.77 with False, 0.95 with True; 23 scenes, seeds 200-201: mean 0.850 -> "
        "0.858)",
        "a point weighs only the filter with the nearest estimated foot (the feet's "
        "Voronoi cells, as the upper-body tracker's eq. 9), within ``gate``",
    )
    refresh_share: float = param(
        0.2,
        "assumed (not in 004: a mixture proposal from the step detector)",
        "share of a filter's particles restarted from a step detected at it",
    )
    shared_foot: float = param(
        0.15, "assumed", "two filters with feet this close track one person", "m"
    )
    birth_exclusion: float = param(
        0.6,
        "measured: at 0.85 no filter started beside a person walking or standing in a "
        "group (neighbours 0.75 m apart); random-groups tuning seeds 0-19 at feet height "
        "MOTP 0.369 at 0.85, 0.494 at 0.6; 004's circle, cross, join, 3 pers., corner, "
        "seeds 0-1: 0.948 both (docs/schenk-tables.md)",
        "no filter starts this close to an existing one; a step detected this close "
        "refreshes the nearest filter",
        "m",
    )
    max_eigenvalue: float = param(
        0.065,
        "departure from 004 (which bounds nothing; 0 here): the upper-body tracker's "
        "bound; at feet height a leg with a carried or pulled suitcase or a long skirt "
        "stays below 0.04, a baggage cart is 0.07-0.11",
        "an object (single-linkage points) whose covariance has a larger largest eigenvalue "
        "is no person's feet: its points start no filter, weigh none and support none; "
        "0 disables",
        "m^2",
    )
    link_distance: float = param(
        0.15,
        "assumed (as upper_body_pf.link_distance)",
        "points closer than this belong to one object (for max_eigenvalue)",
        "m",
    )
    object_memory: float = param(
        0.0,
        "measured (docs/schenk-tables.md): off, cart seeds 200-203 MOTP 0.35 without, 0.16 with "
        "1 s",
        "how long the pieces of an object last seen too big (max_eigenvalue) start no "
        "filter (objects.ObjectMemory); 0 disables",
        "s",
    )
    object_reach: float = param(
        0.1,
        "assumed: 4x the ~0.025 m a walking person's cart moves between scans at 50 Hz",
        "a point this close to a remembered point of the previous scan is remembered "
        "(at 50 Hz; scaled up with the time between scans)",
        "m",
    )
    segment_link: float = param(
        0.06,
        "assumed: 3x the 0.017 m between beams of an LMS151 (0.5 deg) at 2 m",
        "points closer than this form one surface segment (for ``leg_eigenvalue``)",
        "m",
    )
    leg_eigenvalue: float = param(
        0.007,
        "assumed: a leg's arc (<= 0.12 m) is < 0.0015, two legs side by side < 0.005, a "
        "suitcase's 0.40-0.45 m face 0.013-0.017",
        "a surface segment (single linkage at ``segment_link``) whose covariance has a "
        "larger largest eigenvalue is no leg",
        "m^2",
    )
    long_weight: float = param(
        0.1,
        "departure from 004 (1 here: every point weighs the same in eqs. 3-4); carry "
        "case, seeds 200-203: MOTP 0.59 at 1, 0.74 at 0.1, 0.76 at 0.02 (skirt 0.65)",
        "weight in eqs. 3-4 of a point on a surface segment longer than a leg's "
        "(``leg_eigenvalue``); 1 disables",
    )
    rescue_legs: bool = param(
        True,
        "departure from 004 (which bounds no object); False: a too-big object's points "
        "are all dropped; cart, seeds 200-203: MOTP 0.36 with False, 0.50 with True",
        "leg-shaped segments (``leg_eigenvalue``, ``blob_leg_points``) of an object too "
        "big for a person (``max_eigenvalue``) still weigh and support filters (a foot "
        "touching a cart), though they start none",
    )
    blob_body: bool = param(
        True,
        "departure from 004 (False here: always the walking model's body position); "
        "skirt, seeds 200-203: MOTP 0.68 with False, 0.83 with True",
        "a filter whose nearby objects (``link_distance``, within ``blob_reach`` of its "
        "feet midpoint) hold no leg-shaped segment (``leg_eigenvalue``) reports the centre "
        "of those objects (a long skirt: the feet cannot be seen, the skirt moves as one "
        "body) instead of the walking model's body position",
    )
    blob_leg_points: int = param(
        3,
        "assumed: a leg 2-6 m from an LMS151 (0.5 deg) shows 2-6 beams; stray points and "
        "pairs at a skirt's edge are no legs",
        "fewest points of a leg-shaped segment that keeps a filter off its blob",
    )
    blob_reach: float = param(
        0.3,
        "assumed: a skirt's sides are 0.2 m either side of the legs",
        "objects with a point this close to a filter's feet midpoint are its blob",
        "m",
    )
    leg_width: float = param(
        0.12,
        "departure from 004 (0 here: the counts and link as set, for 0.5 deg lasers 2 m "
        "away); random-groups legs are 0.10-0.18 m wide; tuning seeds 0-19 at feet "
        "height, scanners of 0.6-1 deg: MOTP 0.466 at 0, 0.479 at 0.12 "
        "(docs/schenk-tables.md)",
        "width of a leg the laser sees: with b = leg_width / beam spacing (the median "
        "spacing of the scan's foreground points, range x angular step) beams on a leg, "
        "``blob_leg_points`` is at most max(1, floor(b)), ``still_points`` at most "
        "2 max(1, floor(b)), and ``segment_link`` at least ``segment_beams`` spacings; "
        "0 disables",
        "m",
    )
    segment_beams: float = param(
        1.5,
        "assumed: neighbouring beams on a leg's arc lie up to ~1.4 spacings apart",
        "``segment_link`` is at least this many beam spacings (with ``leg_width``)",
    )
    support_radius: float = param(
        0.25, "assumed", "a point this close to a foot supports the filter", "m"
    )
    miss_time: float = param(
        1.0,
        "assumed; 0.2 tuned on 5 simulated 004 runs (lasers on both sides of the walk); "
        "with one laser a passer-by hides a person for longer: feet-crossing and "
        "feet-office, seeds 0-3, MOTP 0.62 at 0.2, 0.65 at 0.5, 0.67 at 1 "
        "(docs/schenk-tables.md)",
        "a filter without support this long dies",
        "s",
    )
    report_time: float = param(
        0.2,
        "assumed: the filters of 004 die after 0.2 s without points (``miss_time`` "
        "before it grew); a filter kept longer is not reported while it coasts",
        "a filter is reported only while it had support this recently",
        "s",
    )
    report_offset: float = param(
        0.06,
        "departure from 004 (0 here: the body the walking model implies); the laser sees "
        "the near side of a leg (radius 0.05-0.09 m) and the feet settle on those points, "
        "0.07 m nearer the laser than the leg MHT's people, whose detections are moved "
        "0.045 m behind the points (random-groups tuning seeds, docs/schenk-tables.md)",
        "the reported body is moved this far along the mean beam direction (from laser to "
        "point, unit vectors averaged) of the points supporting the filter (within "
        "``support_radius`` of a foot): a leg seen by lasers on opposite sides is not moved; "
        "0 disables",
        "m",
    )
    cell_refresh: float = param(
        0.3,
        "departure from 004 (0 here); a filter that stood with its person stays behind when "
        "the person walks off (its particles' strides are near 0 and no step is detected "
        "at a low scan rate); feet-crossing and feet-office, seeds 0-3: MOTP 0.677 at 0, "
        "0.728 at 0.2, 0.752 at 0.3 (docs/schenk-tables.md)",
        "a filter whose Voronoi cell's points (at least ``still_points``) are centred "
        "farther than this from its feet midpoint is refreshed from them (the two halves "
        "along their major axis), as from a detected step; 0 disables",
        "m",
    )
    split_distance: float = param(
        0.5,
        "departure from 004 (0 here: filters never split); in parties 0.5-0.8 m apart "
        "a filter refreshed onto two people stands between them "
        "(:mod:`~laserpeople.tracking.particle.split`)",
        "a filter whose Voronoi cell holds two person-sized blobs (``split_link``) whose "
        "centres lie farther apart than this for ``split_time`` keeps the one nearer its "
        "predicted feet midpoint and a filter starts on the other; 0 disables",
        "m",
    )
    split_time: float = param(
        0.5,
        "assumed: a walker's two legs come together twice per gait period (about 1 s)",
        "how long a filter's cell must hold two people (``split_distance``) to split it",
        "s",
    )
    split_link: float = param(
        0.3,
        "assumed: the legs of a person standing lie within 0.3 m of each other",
        "points closer than this form one person's blob (for ``split_distance``)",
        "m",
    )
    handover_time: float = param(
        2.0,
        "departure from 004 (0 here: every birth a new identity); random-groups tuning "
        "seeds 0-19 at feet height (docs/schenk-tables.md)",
        "a new filter takes over the identity of a track last reported at most this long "
        "ago (and not since) within ``handover_distance`` + ``handover_speed`` x the time "
        "since of where it starts (:mod:`~laserpeople.tracking.particle.handover`); 0 "
        "disables",
        "s",
    )
    handover_distance: float = param(
        0.5,
        "assumed: the birth exclusion's scale (0.6 m)",
        "reach of a lost identity (``handover_time``) at once",
        "m",
    )
    handover_speed: float = param(
        1.5,
        "assumed: a brisk walk (random-groups walkers 0.5-1.5 m/s)",
        "growth of a lost identity's reach with the time since its track was last reported",
        "m/s",
    )
    merge_distance: float = param(
        0.3, "assumed", "a filter this close to an older one is removed", "m"
    )
    keep_identity_age: float = param(
        1.0,
        "departure from 004 (0 here: the survivor always takes the older identity); two "
        "people crossing merge their filters, and the survivor, often the younger filter's "
        "person, carried on under the other's identity: 004's cross scene, tuning seeds 0-8 "
        "with the tracker's seeds 0-2: MOTP 0.931 -> 0.966, runs below 0.7 2 -> 0 of 27 "
        "(docs/schenk-tables.md)",
        "of two filters that merge (``merge_distance``, ``shared_foot``) and are both at "
        "least this old, the survivor keeps its own identity and the other's is lost, for a "
        "new filter nearby to take over (``handover_time``); younger ones (two filters on "
        "one person) leave the survivor the older identity; 0: always the older identity",
        "s",
    )
    stride_range: tuple[float, float] = param(
        (0.15, 1.0), "assumed: adult walking", "initial and allowed stride s", "m"
    )
    period_range: tuple[float, float] = param(
        (0.7, 1.6), "assumed: 1.25-2.9 steps/s", "initial and allowed period T", "s"
    )
    sigma_foot: float = param(0.05, "assumed", "foot position diffusion", "m/sqrt(s)")
    sigma_stride: float = param(0.3, "assumed", "stride diffusion", "m/sqrt(s)")
    sigma_period: float = param(0.2, "assumed", "period diffusion", "s/sqrt(s)")
    sigma_phase: float = param(1.0, "assumed", "phase diffusion", "rad/sqrt(s)")
    sigma_direction: float = param(1.2, "assumed", "direction diffusion", "rad/sqrt(s)")
    confirm_scans: int = param(
        1,
        "assumed; a step sequence already confirms",
        "supported scans before a filter is reported",
    )
    resample_threshold: float = param(
        0.5, "Thrun et al. 2005 (common choice)", "resample when ESS < this x particles"
    )
    seed: int = param(0, "reproducibility", "random seed of the filters")

    leg_reid: bool = param(
        True,
        "measured (docs/trackers.md, the real followed-person recording): identity recall "
        "of the followed person 0.65 -> 0.97; false in the paper preset (004 has none)",
        "give people who come back after a loss their old id by their leg widths ([leg_reid], "
        "identity/leg_width.py)",
    )

    def __post_init__(self) -> None:
        if self.particles < 1:
            raise ConfigError(f"particles must be >= 1, got {self.particles}")
        for name in (
            "delta",
            "h",
            "bandwidth",
            "gate",
            "sigma_repel",
            "segment_link",
            "leg_eigenvalue",
            "blob_reach",
            "split_link",
        ):
            if not getattr(self, name) > 0.0:
                raise ConfigError(f"{name} must be positive, got {getattr(self, name)}")
        if not self.p0 > 0.0:
            raise ConfigError(f"p0 must be positive, got {self.p0}")
        if not self.report_offset >= 0.0:
            raise ConfigError(f"report_offset must be >= 0 m, got {self.report_offset}")
        for name, unit in (
            ("handover_time", "s"),
            ("handover_distance", "m"),
            ("handover_speed", "m/s"),
        ):
            if not getattr(self, name) >= 0.0:
                raise ConfigError(f"{name} must be >= 0 {unit}, got {getattr(self, name)}")
        if not 0.0 <= self.long_weight <= 1.0:
            raise ConfigError(f"long_weight must be in [0, 1], got {self.long_weight}")


def scaled_to_beams(params: FeetParams, spacing: float) -> FeetParams:
    """``params`` with the point counts and segment link of one scan scaled to what its
    laser shows of a leg: with b = ``leg_width`` / ``spacing`` [m] beams on a leg,
    ``blob_leg_points`` at most max(1, floor(b)), ``still_points`` at most
    2 max(1, floor(b)) and ``segment_link`` at least ``segment_beams`` x ``spacing``.
    Unchanged when ``leg_width`` is 0 or ``spacing`` is not a positive number (a frame
    without its scans), and where the laser shows enough beams (a 0.5 deg laser 2 m
    away: b = 6.9)."""
    if params.leg_width <= 0.0 or not spacing > 0.0:
        return params
    beams = max(1, int(np.floor(params.leg_width / spacing)))
    leg_points = min(params.blob_leg_points, beams)
    still_points = min(params.still_points, 2 * beams)
    link = max(params.segment_link, params.segment_beams * spacing)
    if (leg_points, still_points, link) == (
        params.blob_leg_points,
        params.still_points,
        params.segment_link,
    ):
        return params
    return replace(params, blob_leg_points=leg_points, still_points=still_points, segment_link=link)


def foreground_spacing(frame: Frame) -> float:
    """Median beam spacing [m] (range x angular step of its scan) of the frame's
    foreground points; NaN without points or without the scans they came from."""
    from laserpeople.tracking.groups.tracker import beam_spacing

    if frame.points is None or len(frame.points.points) == 0:
        return float("nan")
    idx = (
        np.arange(len(frame.points.points))
        if frame.foreground is None
        else np.flatnonzero(frame.foreground)
    )
    if idx.size == 0:
        return float("nan")
    spacing = beam_spacing(frame, idx)
    return float("nan") if spacing is None else float(np.median(spacing))


def walking_model(states: NDArray[np.float64], dt: float) -> NDArray[np.float64]:
    """004 eqs. 1-2 for states (..., 8) over a time step ``dt`` [s]: the phase advances by
    2 pi dt / T; the left foot moves when mod(gamma_t, 2 pi) > pi, else the right one, by
    s |cos gamma_t - cos gamma_{t-1}| along alpha. Returns a new array."""
    out = np.array(states, dtype=np.float64, copy=True)
    g0 = states[..., GAMMA]
    g1 = g0 + TWO_PI * dt / states[..., T]
    move = states[..., S] * np.abs(np.cos(g1) - np.cos(g0))
    left = np.mod(g1, TWO_PI) > np.pi
    m_l = np.where(left, move, 0.0)
    m_r = np.where(left, 0.0, move)
    ca, sa = np.cos(states[..., ALPHA]), np.sin(states[..., ALPHA])
    out[..., XL] += ca * m_l
    out[..., YL] += sa * m_l
    out[..., XR] += ca * m_r
    out[..., YR] += sa * m_r
    out[..., GAMMA] = g1
    return out


def body_offset(states: NDArray[np.float64]) -> NDArray[np.float64]:
    """Where the body is relative to the feet midpoint under eqs. 1-2 (..., 2) [m].

    In each half period one foot moves s (1 - cos phi), phi = mod(gamma, pi), so the
    midpoint moves (s / 2)(1 - cos phi) while a body walking at the constant speed 2 s / T
    moves s phi / pi; the body is ahead of the midpoint by s (phi / pi - (1 - cos phi) / 2)
    along alpha (zero at phi = 0, pi / 2 and pi)."""
    phi = np.mod(states[..., GAMMA], np.pi)
    ahead = states[..., S] * (phi / np.pi - 0.5 * (1.0 - np.cos(phi)))
    a = states[..., ALPHA]
    return np.asarray(np.stack([ahead * np.cos(a), ahead * np.sin(a)], axis=-1), dtype=np.float64)


def foot_likelihood(
    feet: NDArray[np.float64],
    points: NDArray[np.float64],
    mask: NDArray[np.bool_],
    delta: float,
    p0: float,
    weights: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """004 eqs. 3-4: max(sum_j exp(-|foot - z_j|^2 / (2 delta^2)), P_0) for feet (F, P, 2)
    and the padded points (F, K, 2) of each filter with mask (F, K); returns (F, P). With
    ``weights`` (F, K) each point's kernel is multiplied by its weight (004: all 1)."""
    # |f - z|^2 = |f|^2 + |z|^2 - 2 f.z as one batched product, in float32 (the kernels
    # are summed, so 1e-7 relative error is harmless); padding points are masked out
    f32 = feet.astype(np.float32)
    z32 = points.astype(np.float32)
    d2 = (
        np.einsum("fpc,fpc->fp", f32, f32)[:, :, None]
        + np.where(mask, np.einsum("fkc,fkc->fk", z32, z32), np.float32(1e6))[:, None, :]
        - 2.0 * np.matmul(f32, z32.transpose(0, 2, 1))
    )
    kernel = np.exp(np.maximum(d2, 0.0) * np.float32(-0.5 / (delta * delta)))
    if weights is not None:
        kernel = kernel * weights.astype(np.float32)[:, None, :]
    total = kernel.sum(axis=2, dtype=np.float64)
    return np.asarray(np.maximum(total, p0), dtype=np.float64)


def stride_likelihood(states: NDArray[np.float64], h: float) -> NDArray[np.float64]:
    """004 eqs. 5-6: s_d = (x_r - x_l) cos alpha + (y_r - y_l) sin alpha and
    o_b = exp(-(s_d + s cos gamma)^2 / (2 h^2)), for states (..., 8)."""
    a = states[..., ALPHA]
    s_d = (states[..., XR] - states[..., XL]) * np.cos(a) + (
        states[..., YR] - states[..., YL]
    ) * np.sin(a)
    r = s_d + states[..., S] * np.cos(states[..., GAMMA])
    return np.asarray(np.exp(-(r * r) / (2.0 * h * h)), dtype=np.float64)


def width_likelihood(states: NDArray[np.float64], width: float, h: float) -> NDArray[np.float64]:
    """The feet's sideways distance s_w = |-(x_r - x_l) sin alpha + (y_r - y_l) cos alpha|
    scored against the step width: exp(-(s_w - width)^2 / (2 h^2)) for states (..., 8);
    all ones when ``h`` is 0 (004 has no such term)."""
    if h <= 0.0:
        return np.ones(states.shape[:-1])
    a = states[..., ALPHA]
    s_w = np.abs(
        -(states[..., XR] - states[..., XL]) * np.sin(a)
        + (states[..., YR] - states[..., YL]) * np.cos(a)
    )
    r = s_w - width
    return np.asarray(np.exp(-(r * r) / (2.0 * h * h)), dtype=np.float64)


def feet_weights(
    states: NDArray[np.float64],
    points: NDArray[np.float64],
    mask: NDArray[np.bool_],
    p: FeetParams,
    weights: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """004 eq. 7: w = o_l o_r o_b for states (F, P, 8) and padded points (F, K, 2), the
    points' kernels in eqs. 3-4 multiplied by ``weights`` (F, K) if given."""
    o_l = foot_likelihood(states[..., XL : YL + 1], points, mask, p.delta, p.p0, weights)
    o_r = foot_likelihood(states[..., XR : YR + 1], points, mask, p.delta, p.p0, weights)
    o_b = stride_likelihood(states, p.h) * width_likelihood(states, p.step_width, p.h_width)
    return o_l * o_r * o_b


def repelling(
    midpoints: NDArray[np.float64], estimates: NDArray[np.float64], sigma: float
) -> NDArray[np.float64]:
    """Repelling factor (F, P): prod over other filters g of
    1 - exp(-|c_fi - e_g|^2 / (2 sigma^2)) for particle midpoints ``midpoints`` (F, P, 2)
    and filter estimates ``estimates`` (F, 2)."""
    f = midpoints.shape[0]
    d = midpoints[:, :, None, :] - estimates[None, None, :, :]
    d2 = np.einsum("fpgc,fpgc->fpg", d, d)
    factor = 1.0 - np.exp(-d2 / (2.0 * sigma * sigma))
    own = np.arange(f)
    factor[own, :, own] = 1.0  # a filter does not repel itself
    return np.asarray(np.prod(factor, axis=2), dtype=np.float64)


@dataclass(frozen=True)
class StepEvent:
    """A merge or split of feet clusters: where [m], when [s], and for a split the two
    clusters' centres (2, 2)."""

    kind: str
    position: NDArray[np.float64]
    stamp: float
    feet: NDArray[np.float64]


class StepDetector:
    """Finds the merge -> split sequence of a step (004 Fig. 1) in consecutive scans."""

    def __init__(self, params: FeetParams) -> None:
        self.params = params
        self._prev: tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]] | None = None
        self._merges: list[StepEvent] = []
        self._stamp: float | None = None

    def events(
        self, points: NDArray[np.float64], stamp: float
    ) -> tuple[list[StepEvent], list[StepEvent]]:
        """Merges and splits between the previous scan and ``points`` (N, 2)."""
        p = self.params
        if len(points):
            ms = mean_shift(points, p.bandwidth)
            labels, centres = ms.labels, ms.centres
        else:
            labels, centres = np.empty(0, np.int64), np.empty((0, 2))
        prev = self._prev
        self._prev = (points, labels, centres)
        dt = stamp - self._stamp if self._stamp is not None else 0.02
        self._stamp = stamp
        # feet move farther between slower scans: widen the link distance beyond 50 Hz
        reach = p.overlap_distance * max(1.0, dt / 0.02)
        if p.overlap_max > 0.0:
            reach = min(reach, max(p.overlap_max, p.overlap_distance))
        merges: list[StepEvent] = []
        splits: list[StepEvent] = []
        if prev is None or len(points) == 0 or len(prev[0]) == 0:
            return merges, splits
        old_pts, old_labels, _ = prev
        # distinct (new cluster, old cluster) pairs, as one integer key each
        width = int(old_labels.max()) + 1
        key = cluster_links(points, labels, old_pts, old_labels, reach)
        links = np.column_stack([key // width, key % width])
        if len(links) == 0:
            return merges, splits
        new_ids, new_count = np.unique(links[:, 0], return_counts=True)
        for b in new_ids[new_count >= 2]:
            merges.append(StepEvent("merge", centres[b], stamp, np.empty((0, 2))))
        old_ids, old_count = np.unique(links[:, 1], return_counts=True)
        for a in old_ids[old_count == 2]:
            parts = links[links[:, 1] == a, 0]
            feet = centres[parts]
            splits.append(StepEvent("split", feet.mean(axis=0), stamp, feet))
        return merges, splits

    def detections(self, points: NDArray[np.float64], stamp: float) -> list[StepEvent]:
        """Splits of this scan that complete a merge -> split sequence."""
        p = self.params
        merges, splits = self.events(points, stamp)
        self._merges = [m for m in self._merges if stamp - m.stamp <= p.sequence_time]
        found = []
        for s in splits:
            if any(
                np.hypot(*(s.position - m.position)) <= p.sequence_distance for m in self._merges
            ):
                found.append(s)
        self._merges.extend(merges)
        return found


class StillDetector:
    """Finds people who stand still (a departure from 004, whose step sequence needs a
    walking person): a person-sized object (single linkage at ``link_distance``, at least
    ``still_points`` points, largest covariance eigenvalue at most ``still_eigenvalue``)
    whose centre has stayed within ``still_move`` of where it was first seen for
    ``still_time``."""

    def __init__(self, params: FeetParams) -> None:
        self.params = params
        self._anchors = np.empty((0, 2))
        self._since = np.empty(0)

    def detections(
        self,
        points: NDArray[np.float64],
        stamp: float,
        labels: NDArray[np.int64] | None = None,
    ) -> list[NDArray[np.float64]]:
        """The feet (2, 2) [m] of every object of ``points`` (N, 2) (single linkage at
        ``link_distance``; their ``labels`` (N,) if known) that has been still for
        ``still_time`` [s] by ``stamp``: its points split in two along its major axis (the
        two legs), each half's centre."""
        p = self.params
        if p.still_time <= 0.0 or len(points) == 0:
            self._anchors, self._since = np.empty((0, 2)), np.empty(0)
            return []
        if labels is None:
            labels = single_linkage(points, p.link_distance)
        n = int(labels.max()) + 1
        mean, cov, count = cluster_covariances(points, labels, n)
        ok = np.flatnonzero(
            (count >= p.still_points) & (largest_eigenvalue(cov) <= p.still_eigenvalue)
        )
        anchors, since = mean[ok], np.full(ok.size, stamp)
        if len(self._anchors) and ok.size:
            d, j = cKDTree(self._anchors).query(anchors, k=1, distance_upper_bound=p.still_move)
            kept = np.isfinite(d)
            anchors[kept] = self._anchors[j[kept]]
            since[kept] = self._since[j[kept]]
        self._anchors, self._since = anchors, since
        still = ok[stamp - since >= p.still_time]
        return [two_feet(points[labels == k], mean[k], cov[k]) for k in still]


class FeetTracker:
    """Multi-person tracker at feet height (004 Sec. 2.1); a ``FrameTracker`` on the fused
    foreground points of the feet-height lasers."""

    consumes: frozenset[FrameField] = frozenset({"points", "foreground"})
    needs_steady_points = True
    """A filter dies after ``miss_time`` without points: on a moving laser the pipeline's
    foreground of points near legs holds missed legs for it
    (:mod:`laserpeople.pipeline.leg_foreground`)."""

    def __init__(self, params: FeetParams | None = None) -> None:
        self.params = params or FeetParams()
        self.rng = np.random.default_rng(self.params.seed)
        self.bank = FilterBank(self.params.particles, 8)
        self.detector = StepDetector(self.params)
        self.still = StillDetector(self.params)
        self.unclaimed = UnclaimedDetector(self.params)
        self.splitter = PartySplitter(self.params)
        self.scaled = self.params
        """The parameters of the last scan (:func:`scaled_to_beams`)."""
        self._stamp: float | None = None
        self.objects = ObjectMemory(self.params.object_reach, self.params.object_memory)
        p = self.params
        self.lost = LostIdentities(p.handover_time, p.handover_distance, p.handover_speed)
        self._shown = np.empty(0, dtype=np.int64)
        """Identities reported in the last scan."""

    def _predict(self, dt: float) -> None:
        p, bank = self.params, self.bank
        if len(bank) == 0 or dt <= 0.0:
            return
        s = walking_model(bank.states, dt)
        root = np.sqrt(dt)
        shape = s.shape[:2]
        for col, sig in (
            (XL, p.sigma_foot),
            (YL, p.sigma_foot),
            (XR, p.sigma_foot),
            (YR, p.sigma_foot),
            (S, p.sigma_stride),
            (T, p.sigma_period),
            (GAMMA, p.sigma_phase),
            (ALPHA, p.sigma_direction),
        ):
            s[..., col] += self.rng.normal(0.0, sig * root, shape)
        s[..., S] = np.clip(s[..., S], 0.0, p.stride_range[1])
        s[..., T] = np.clip(s[..., T], *p.period_range)
        bank.states = s

    def midpoints(self) -> NDArray[np.float64]:
        """Feet midpoints (F, P, 2) of every particle."""
        st = self.bank.states
        return np.asarray(0.5 * (st[..., XL : YL + 1] + st[..., XR : YR + 1]), dtype=np.float64)

    def update(self, frame: Frame) -> Tracks:
        """Predict, weight by eqs. 3-7 and the repelling term, resample, remove dead
        filters and start filters at completed step sequences."""
        bank = self.bank
        pts = frame.foreground_points("the feet tracker")
        rays = (
            beam_directions(frame, "the feet tracker") if self.params.report_offset > 0.0 else None
        )
        p = self.scaled = scaled_to_beams(
            self.params, foreground_spacing(frame) if self.params.leg_width > 0.0 else math.nan
        )
        self.still.params = self.unclaimed.params = self.splitter.params = p
        # one clustering per scan at link_distance and one at segment_link, shared by the
        # size bound, the still detector, the weights of eqs. 3-4 and the blob centres
        wants_objects = p.max_eigenvalue > 0.0 or p.still_time > 0.0 or p.blob_body
        objects = single_linkage(pts, p.link_distance) if wants_objects and len(pts) else None
        sized = small_objects(pts, p.link_distance, p.max_eigenvalue, objects)
        remembered = self.objects.update(pts, ~sized, frame.stamp)
        births = pts[~remembered]
        birth_objects = _kept(pts, objects, ~remembered, p.link_distance)
        segments = None
        if p.rescue_legs and len(pts) and not sized.all():
            segments = single_linkage(pts, p.segment_link)
            legs = _leg_segments(pts, p.segment_link, p.leg_eigenvalue, p.blob_leg_points, segments)
            sized = sized | legs
        objects = _kept(pts, objects, sized, p.link_distance)
        segments = _kept(pts, segments, sized, p.segment_link)
        pts = pts[sized]
        rays = None if rays is None else rays[sized]
        if segments is None and len(pts) and (p.long_weight != 1.0 or p.blob_body):
            segments = single_linkage(pts, p.segment_link)
        dt = 0.0 if self._stamp is None else frame.stamp - self._stamp
        self._stamp = frame.stamp
        self._predict(dt)
        splits: list[Split] = []
        if len(bank):
            mids = self.midpoints()
            est = np.einsum("fp,fpc->fc", bank.weights, mids)
            if p.voronoi:
                # a point belongs to the filter with the nearest estimated foot
                cell = voronoi_cells(pts, bank.mean([XL, YL, XR, YR]).reshape(-1, 2), p.gate)
                inside = np.flatnonzero(cell >= 0)
                near = (inside, cell[inside] // 2)
                if p.cell_refresh > 0.0:
                    self._cell_refresh(pts[inside], near[1], est)
                if p.split_distance > 0.0:
                    splits = self.splitter.splits(pts[inside], near[1], bank.ids, est, frame.stamp)
                    for sp in splits:  # the filter restarts on the person it keeps
                        bank.states[sp.filter] = self._initial(sp.keep)
                        bank.weights[sp.filter] = 1.0 / p.particles
            else:
                near = _points_near(pts, est, p.gate)
            rows = np.column_stack([pts, self._leg_weights(pts, segments)])
            local, mask = (
                gather_cells(rows[near[0]], near[1], len(bank))
                if near[0].size
                else (
                    np.zeros((len(bank), 1, 3)),
                    np.zeros((len(bank), 1), dtype=bool),
                )
            )
            lik = feet_weights(bank.states, local[..., :2], mask, p, local[..., 2])
            if len(bank) > 1:
                lik = lik * repelling(mids, est, p.sigma_repel)
            bank.reweight(lik + 1e-300, self.rng, p.resample_threshold)
            feet_est = bank.mean([XL, YL, XR, YR]).reshape(-1, 2, 2)
            supported = _supported(pts, feet_est, p.support_radius)
            bank.support(supported, frame.stamp)
            self._cull(frame.stamp)
        self._births(births, frame.stamp, birth_objects, [sp.new for sp in splits])
        return self._report(frame, pts, objects, segments, rays)

    def _leg_weights(
        self, pts: NDArray[np.float64], segments: NDArray[np.int64] | None = None
    ) -> NDArray[np.float64]:
        """(N,) weight of each point in eqs. 3-4: ``long_weight`` on a surface segment
        (single linkage at ``segment_link``; ``segments`` (N,) labels if known) longer than
        a leg's (``leg_eigenvalue``), else 1."""
        p = self.scaled
        if p.long_weight == 1.0 or len(pts) == 0:
            return np.ones(len(pts))
        long = object_eigenvalues(pts, p.segment_link, segments) > p.leg_eigenvalue
        return np.where(long, p.long_weight, 1.0)

    def _cull(self, stamp: float) -> None:
        """Remove filters without support for ``miss_time``; of two filters that come
        within ``merge_distance`` or share a foot (feet within ``shared_foot``), keep the
        one with the better smoothed likelihood, under the older identity unless both are
        ``keep_identity_age`` old."""
        p, bank = self.params, self.bank
        pairs: list[tuple[int, int]] = []
        if len(bank) > 1:
            est = np.einsum("fp,fpc->fc", bank.weights, self.midpoints())
            close = close_pairs(est, p.merge_distance)
            pairs = [(int(a), int(b)) for a, b in close]
            flat = bank.mean([XL, YL, XR, YR]).reshape(-1, 2)
            shared = close_pairs(flat, p.shared_foot)
            pairs += [(int(a) // 2, int(b) // 2) for a, b in shared]
        bank.cull(stamp, p.miss_time, pairs, by_quality=True, keep_identity_age=p.keep_identity_age)

    def _births(
        self,
        pts: NDArray[np.float64],
        stamp: float,
        objects: NDArray[np.int64] | None = None,
        split: list[NDArray[np.float64]] | None = None,
    ) -> None:
        """Start filters at step sequences, still objects, unclaimed walkers and the
        other person of a split filter (``split``: feet (2, 2) [m] each; no birth
        exclusion for them)."""
        p, bank = self.params, self.bank
        found = self.detector.detections(pts, stamp)
        still = self.still.detections(pts, stamp, objects)
        free: list[NDArray[np.float64]] = []
        if p.claim_distance > 0.0:
            on = bank.mean([XL, YL, XR, YR]).reshape(-1, 2, 2) if len(bank) else np.empty((0, 2, 2))
            free = self.unclaimed.detections(pts, stamp, on, objects)
        if not (found or still or free or split):
            return
        est = (
            np.einsum("fp,fpc->fc", bank.weights, self.midpoints())
            if len(bank)
            else np.empty((0, 2))
        )
        starts: list[NDArray[np.float64]] = list(split or [])
        for ev in found:
            if len(est):
                dist = np.hypot(*(est - ev.position).T)
                near = int(np.argmin(dist))
                if dist[near] <= p.birth_exclusion:
                    self._refresh(near, ev.feet)
                    continue
            if any(np.hypot(*(ev.position - f.mean(axis=0))) <= p.birth_exclusion for f in starts):
                continue
            starts.append(ev.feet)
        for feet in still:  # a person standing still: no refresh, a filter where none is
            mid = feet.mean(axis=0)
            if len(est) and np.hypot(*(est - mid).T).min() <= p.birth_exclusion:
                continue
            if any(np.hypot(*(mid - f.mean(axis=0))) <= p.birth_exclusion for f in starts):
                continue
            starts.append(feet)
        for two in free:  # no filter's foot near: births closer than birth_exclusion
            if any(
                np.hypot(*(two.mean(axis=0) - f.mean(axis=0))) <= p.birth_exclusion for f in starts
            ):
                continue
            starts.append(two)
        if starts:
            first = len(bank)
            bank.add(np.stack([self._initial(f) for f in starts]), stamp)
            self._hand_over(np.stack([f.mean(axis=0) for f in starts]), first, stamp)

    def _hand_over(self, starts: NDArray[np.float64], first: int, stamp: float) -> None:
        """The new filters ``first``.. starting at ``starts`` (K, 2) [m] take over the
        identities of tracks lost nearby (:class:`LostIdentities`); a filter that still
        holds such an identity unreported is removed."""
        bank = self.bank
        taken = self.lost.take(starts, self._shown, stamp)
        gone = np.zeros(len(bank), dtype=bool)
        for k, got in enumerate(taken):
            if got is None:
                continue
            identity, born = got
            gone |= bank.ids == identity
            bank.ids[first + k] = identity
            bank.born[first + k] = born
        if gone.any():
            bank.keep(~gone)

    def _cell_refresh(
        self, pts: NDArray[np.float64], owner: NDArray[np.int64], est: NDArray[np.float64]
    ) -> None:
        """Refresh (:meth:`_refresh`) every filter whose cell's points ``pts`` (N, 2)
        (filter ``owner`` (N,)), at least ``still_points`` of them, are centred farther
        than ``cell_refresh`` from its feet midpoint ``est`` (F, 2): from the two halves
        of those points along their major axis
        (:func:`~laserpeople.tracking.particle.objects.two_feet`)."""
        p = self.scaled
        if len(pts) == 0:
            return
        n = len(est)
        mean, cov, count = cluster_covariances(pts, owner, n)
        off = np.hypot(*(mean - est).T)
        for f in np.flatnonzero((count >= p.still_points) & (off > p.cell_refresh)):
            self._refresh(int(f), two_feet(pts[owner == f], mean[f], cov[f]))

    def _refresh(self, f: int, feet: NDArray[np.float64]) -> None:
        """A step detected at filter ``f``: replace a share ``refresh_share`` of its
        particles, drawn at random, by particles started from the detected feet (a mixture
        proposal), each with the filter's mean weight, so that the next weighting chooses
        between the filter's belief and the detection."""
        p, bank = self.params, self.bank
        k = round(p.refresh_share * p.particles)
        if k == 0:
            return
        idx = self.rng.choice(p.particles, size=k, replace=False)
        bank.states[f, idx] = self._initial(feet)[:k]
        bank.weights[f, idx] = 1.0 / p.particles
        bank.weights[f] /= bank.weights[f].sum()

    def _initial(self, feet: NDArray[np.float64]) -> NDArray[np.float64]:
        """Particles (P, 8) for a person whose feet clusters are ``feet`` (2, 2): the walking
        direction along the feet (either sense), either foot the left one, stride and period
        from their ranges, and the phase that makes eq. 6 hold exactly."""
        p, rng, n = self.params, self.rng, self.params.particles
        a, b = feet
        base = float(np.arctan2(*(b - a)[::-1]))
        alpha = base + np.pi * rng.integers(0, 2, n) + rng.normal(0.0, 0.15, n)
        u = np.column_stack([np.cos(alpha), np.sin(alpha)])
        proj = (b - a) @ u.T  # (P,) b ahead of a along alpha when > 0
        front = np.where(proj[:, None] > 0, b, a)
        back = np.where(proj[:, None] > 0, a, b)
        gap = np.abs(proj)
        stride = rng.uniform(*p.stride_range, n)
        stride = np.maximum(stride, gap + 0.01)
        right_front = rng.integers(0, 2, n).astype(bool)
        ratio = np.clip(gap / stride, 0.0, 1.0)
        # right foot ahead: s_d = +gap = -s cos(gamma), gamma in (pi/2, pi] (right moving)
        # left foot ahead: s_d = -gap = -s cos(gamma), gamma in [3pi/2, 2pi) (left moving)
        gamma = np.where(right_front, np.arccos(-ratio), TWO_PI - np.arccos(ratio))
        st = np.empty((n, 8))
        left = np.where(right_front[:, None], back, front)
        right = np.where(right_front[:, None], front, back)
        st[:, XL : YL + 1] = left + rng.normal(0.0, 0.02, (n, 2))
        st[:, XR : YR + 1] = right + rng.normal(0.0, 0.02, (n, 2))
        st[:, S] = stride
        st[:, T] = rng.uniform(*p.period_range, n)
        st[:, GAMMA] = gamma
        st[:, ALPHA] = alpha
        return st

    def _velocities(self) -> NDArray[np.float64]:
        """Body velocities (F, P, 2) [m/s] of every particle: 2 s / T along alpha (the body
        covers two strides per period)."""
        st = self.bank.states
        speed = 2.0 * st[..., S] / st[..., T]
        return np.asarray(
            np.stack([speed * np.cos(st[..., ALPHA]), speed * np.sin(st[..., ALPHA])], -1),
            dtype=np.float64,
        )

    def _report(
        self,
        frame: Frame,
        pts: NDArray[np.float64],
        objects: NDArray[np.int64] | None = None,
        segments: NDArray[np.int64] | None = None,
        rays: NDArray[np.float64] | None = None,
    ) -> Tracks:
        """Tracks at the body positions the walking model implies (feet midpoint moved by
        :func:`body_offset`), moving at 2 s / T along alpha; a filter on a blob without
        legs (``blob_body``) at the blob's centre (:func:`blob_centres`); then moved
        ``report_offset`` along the beams of its supporting points (``rays`` (N, 2), unit
        vectors of ``pts``; :func:`beyond_surface`). ``objects`` and ``segments`` (N,) are
        the labels of ``pts`` at ``link_distance`` and ``segment_link`` if known."""
        p, st = self.scaled, self.bank.states
        body = self.midpoints() + body_offset(st)
        vel = self._velocities()
        if p.blob_body and len(self.bank) and len(pts):
            mids = np.einsum("fp,fpc->fc", self.bank.weights, self.midpoints())
            est = np.einsum("fp,fpc->fc", self.bank.weights, body)
            heading = np.einsum("fp,fpc->fc", self.bank.weights, vel)
            legs = _leg_segments(pts, p.segment_link, p.leg_eigenvalue, p.blob_leg_points, segments)
            centre = blob_centres(pts, legs, mids, heading, p.link_distance, p.blob_reach, objects)
            shift = np.where(np.isfinite(centre), centre - est, 0.0)
            body = body + shift[:, None, :]
        if rays is not None and len(self.bank) and len(pts):
            feet = self.bank.mean([XL, YL, XR, YR]).reshape(-1, 2, 2)
            shift = beyond_surface(pts, rays, feet, p.support_radius, p.report_offset)
            body = body + shift[:, None, :]
        shown = frame.stamp - self.bank.last_seen <= p.report_time
        out = self.bank.tracks(body, vel, p.confirm_scans, frame, shown)
        if p.handover_time > 0.0:  # (004's filters, handover_time 0: nothing to remember)
            reported = np.flatnonzero((self.bank.hits >= p.confirm_scans) & shown)
            ids = self.bank.ids[reported]
            positions = np.array([t.position for t in out], dtype=np.float64).reshape(-1, 2)
            self.lost.reported(ids, positions, self.bank.born[reported], frame.stamp)
            self._shown = ids
        return out


def blob_centres(
    points: NDArray[np.float64],
    legs: NDArray[np.bool_],
    anchors: NDArray[np.float64],
    headings: NDArray[np.float64],
    link_distance: float,
    reach: float,
    labels: NDArray[np.int64] | None = None,
) -> NDArray[np.float64]:
    """Centres (F, 2) [m] of the blobs of F filters, NaN where a filter has none.

    A filter's blob is the union of the objects (single linkage of ``points`` (N, 2) at
    ``link_distance``; their ``labels`` (N,) if known) with a point within ``reach`` of
    its ``anchor`` (F, 2), when no point of them is leg-shaped (``legs`` (N,) False
    everywhere). Its centre is the middle of its extent along the filter's ``heading``
    (F, 2) (the sides a laser sees of a body passing it lie ahead of the body before the
    laser and behind it afterwards, while the extent spans the body) and the mean of its
    points across it; the mean of its points when the heading is zero."""
    out = np.full((len(anchors), 2), np.nan)
    if len(points) == 0 or len(anchors) == 0:
        return out
    if labels is None:
        labels = single_linkage(points, link_distance)
    n = int(labels.max()) + 1
    has_leg = np.bincount(labels, weights=legs.astype(np.float64), minlength=n) > 0
    near = kdtree(points).query_ball_point(anchors, reach)
    for f, idx in enumerate(near):
        objs = np.unique(labels[np.asarray(idx, dtype=np.int64)])
        if objs.size == 0 or has_leg[objs].any():
            continue
        blob = points[np.isin(labels, objs)]
        centre = blob.mean(axis=0)
        norm = float(np.hypot(*headings[f]))
        if norm > 0.0:
            u = headings[f] / norm
            along = (blob - centre) @ u
            centre = centre + u * 0.5 * (along.max() + along.min())
        out[f] = centre
    return out


def _leg_segments(
    points: NDArray[np.float64],
    link: float,
    max_eigenvalue: float,
    min_points: int,
    labels: NDArray[np.int64] | None = None,
) -> NDArray[np.bool_]:
    """(N,) True for the points of surface segments (single linkage at ``link`` [m]; their
    ``labels`` (N,) if known) of at least ``min_points`` points whose largest covariance
    eigenvalue is at most ``max_eigenvalue`` [m^2]: leg-shaped."""
    if labels is None:
        labels = single_linkage(points, link)
    n = int(labels.max()) + 1
    _, cov, count = cluster_covariances(points, labels, n)
    leg = (largest_eigenvalue(cov) <= max_eigenvalue) & (count >= min_points)
    return np.asarray(leg[labels], dtype=bool)


def _kept(
    points: NDArray[np.float64],
    labels: NDArray[np.int64] | None,
    keep: NDArray[np.bool_],
    link: float,
) -> NDArray[np.int64] | None:
    """The labels of ``points[keep]`` from ``labels`` of all ``points`` (None stays None;
    :func:`~laserpeople.tracking.particle.objects.kept_labels`)."""
    return None if labels is None else kept_labels(points, labels, keep, link)


def _points_near(
    points: NDArray[np.float64], centres: NDArray[np.float64], radius: float
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(point index, filter index) pairs within ``radius`` (a point may serve several
    filters; the repelling term keeps them apart)."""
    if len(points) == 0 or len(centres) == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    m = cKDTree(centres).sparse_distance_matrix(kdtree(points), radius, output_type="ndarray")
    return m["j"].astype(np.int64), m["i"].astype(np.int64)


def beyond_surface(
    points: NDArray[np.float64],
    rays: NDArray[np.float64],
    feet: NDArray[np.float64],
    radius: float,
    offset: float,
) -> NDArray[np.float64]:
    """(F, 2) shift [m] of each filter's reported body: ``offset`` times the mean of the
    unit beam directions ``rays`` (N, 2) of the ``points`` (N, 2) within ``radius`` of
    either of its feet (F, 2, 2) (a point near two filters counts for both); 0 for a
    filter without such points. Beams from opposite sides cancel."""
    n_filters = len(feet)
    point, foot = _points_near(points, feet.reshape(-1, 2), radius)
    pair = np.unique(point * n_filters + foot // 2)  # a point near both feet counts once
    point, filt = pair // n_filters, pair % n_filters
    total = np.zeros((n_filters, 2))
    np.add.at(total, filt, rays[point])
    count = np.bincount(filt, minlength=n_filters)[:, None]
    return offset * total / np.maximum(count, 1)


def _supported(
    points: NDArray[np.float64], feet: NDArray[np.float64], radius: float
) -> NDArray[np.bool_]:
    """(F,) True where a point lies within ``radius`` of either estimated foot (F, 2, 2)."""
    if len(points) == 0 or len(feet) == 0:
        return np.zeros(len(feet), dtype=bool)
    d, _ = nearest(feet.reshape(-1, 2), points)
    return np.asarray((d.reshape(-1, 2) <= radius).any(axis=1), dtype=bool)


__all__ = [
    "FeetParams",
    "FeetTracker",
    "StepDetector",
    "StepEvent",
    "beyond_surface",
    "blob_centres",
    "body_offset",
    "feet_weights",
    "foot_likelihood",
    "foreground_spacing",
    "repelling",
    "scaled_to_beams",
    "stride_likelihood",
    "walking_model",
    "width_likelihood",
]
