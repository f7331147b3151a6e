"""grip: grasp mechanics for haptics and robotics.

The grasp matrix of a set of contacts, the contact forces nearest given squeezing forces
that balance an object's external wrench (with or without Coulomb friction cones), and
force closure, on the C++ library grip. Units: metres, newtons, newton metres; normals are
unit and point INTO the object; forces are those the contacts apply ON the object.
"""

from ._grip import (
    ConicAnalysisSettings,
    ConstrainedSettings,
    ConstrainedSolution,
    ForceClosure,
    Grasp,
    Model,
    Solution,
    Status,
    force_closure,
    max_contacts,
    solve_constrained,
    solve_kkt,
    solve_range_space,
)

__all__ = [
    "ConicAnalysisSettings",
    "ConstrainedSettings",
    "ConstrainedSolution",
    "ForceClosure",
    "Grasp",
    "Model",
    "Solution",
    "Status",
    "force_closure",
    "max_contacts",
    "solve_constrained",
    "solve_kkt",
    "solve_range_space",
]
