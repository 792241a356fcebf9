"""The Vision system's image-processing routines: what one look registers, by its purpose.

The learning paper, section 5.3: "The vision system can either search for new landmarks or
re-acquire already-detected landmarks, but it is not able to do both things at the same time,
because different image processing routines are required for each. In either case, however, the
vision system returns the heading and distance to the landmarks it detects." Whoever wins the
camera says what the look is for (:data:`navcli.bidding.PURPOSES`), and the image is processed by
that purpose's routine alone:

=============  ===================================  ==============================================
purpose        who asks                             what the image registers
=============  ===================================  ==============================================
``search``     MLL, the Risk Manager, the           the landmarks the memory does not hold (the
               Rescuer's sweep and exploring looks  target among them while it is not known)
``landmarks``  MVL                                  the landmarks the memory holds, not the target
``target``     MVT, MOT, the Target Tracker, the    the target, known or not
               Distance Estimator
``scan``       the Rescuer's scans for a lost       the target, and the landmarks the memory holds
               target
``obstacles``  the Pilot's look ahead (eq. 1) and   the obstacles: point obstacles, fences and the
               its looks round a bump               room's walls, and any landmark the memory does
                                                    not hold, as a plain point obstacle
=============  ===================================  ==============================================

Where the papers are silent, our reading (each a choice, stated here and in the docs):

- **The target is a landmark the robot can recognise** ("a target landmark that the robot is able
  to recognize visually", the learning paper's introduction): a search finds it while the memory
  does not hold it, as any new landmark; a look for the target re-acquires it wherever it is in
  view, known or not (its appearance is known); the Rescuer's scan looks for it too, and
  re-acquires the known landmarks besides, from which the map can place it (both are
  re-acquisitions, one routine).
- **Obstacles are found by the obstacle routine only** (the Pilot's looks: "the Pilot also makes
  bids for camera control, to look ahead ... for gathering additional information about
  obstacles", pilot paper, section 3): a search or a re-acquisition does not register fences,
  walls or point obstacles. They still hide what is behind them (occlusion is the image's, not a
  routine's).
- **A landmark is an obstacle to the Pilot's look** (the pilot paper grows landmarks into
  prohibited circles like point obstacles): the obstacle routine does not identify landmarks, so
  one the memory holds is left as it is (it is known already, and is not re-measured), and one it
  does not hold is registered as a plain point obstacle, which the memory drops once a landmark
  routine identifies the landmark there.
- **Target markers** (a point target's, a line target's two) are not physical: the obstacle
  routine never registers them.

``vision.walls`` decides whether walls are registered at all (``felt``: never; the bumpers find
them), and ``vision.routines`` 0 gives a camera whose every image registers
everything in view (:data:`EVERYTHING`).
"""

from __future__ import annotations

from typing import Container, Literal

from ..bidding import LookPurpose

Registered = Literal["as-is", "as-obstacle"] | None
"""How an image registers an object: identified, as what it is (``as-is``); as a plain obstacle
that the routine does not identify (``as-obstacle``); or not at all (None)."""
EVERYTHING: LookPurpose = "everything"
"""The purpose of an image under ``vision.routines`` 0: every object in view, as before."""


def registers(purpose: LookPurpose, kind: str, key: str, known: Container[str], target: Container[str]) -> Registered:
    """How a look for ``purpose`` registers an object of ``kind`` (a scenario object's:
    ``landmark``, ``target`` (a marker), ``circle``, ``segment`` or ``wall``) whose key is
    ``key``, when the memory holds the keys ``known`` and the target's keys are ``target``
    (see the module docstring).

    >>> known, target = {"A", "T"}, {"T"}
    >>> [registers("search", "landmark", k, known, target) for k in ("A", "B", "T")]
    [None, 'as-is', None]
    >>> [registers("landmarks", "landmark", k, known, target) for k in ("A", "B", "T")]
    ['as-is', None, None]
    >>> [registers("target", "landmark", k, known, target) for k in ("A", "T")]
    [None, 'as-is']
    >>> [registers("obstacles", kind, k, known, target) for kind, k in
    ...  (("landmark", "A"), ("landmark", "B"), ("circle", "o1"), ("segment", "o2"), ("target", "target"))]
    [None, 'as-obstacle', 'as-obstacle', 'as-is', None]
    """
    if purpose == EVERYTHING:
        return "as-obstacle" if kind == "circle" else "as-is"
    if kind == "landmark" or kind == "target":
        if purpose == "obstacles":  # a marker is not physical; a landmark is, unidentified
            return "as-obstacle" if kind == "landmark" and key not in known else None
        if key in target:
            return "as-is" if purpose in ("target", "scan") or (purpose == "search" and key not in known) else None
        if kind == "target" or purpose == "target":
            return None
        if purpose == "search":
            return None if key in known else "as-is"
        return "as-is" if key in known else None  # landmarks, scan: the known ones re-acquired
    if purpose != "obstacles":
        return None
    return "as-obstacle" if kind == "circle" else "as-is"
