"""grip: grasp mechanics for haptics and robotics.

The grasp matrix of a set of contacts, the contact forces nearest given squeezing forces
that balance an object's external wrench (with or without Coulomb friction cones), and
force closure, grasp quality and epsilon, and batches of thousands of candidate grasps on
all cores (grip.batch), on the C++ library grip. Units: metres, newtons, newton metres; normals are
unit and point INTO the object; forces are those the contacts apply ON the object.
"""

from ._grip import (
    ConicAnalysisSettings,
    ConstrainedSettings,
    ConstrainedSolution,
    ContactMode,
    Epsilon,
    ForceClosure,
    Grasp,
    GraspQuality,
    HandDimensions,
    Model,
    MonitorReport,
    Primitive,
    Shape,
    Solution,
    Status,
    box,
    capsule,
    cylinder,
    decompose_forces,
    epsilon,
    force_closure,
    forward_kinematics,
    grasp_quality,
    hand_contacts,
    max_contacts,
    monitor,
    solve_constrained,
    solve_kkt,
    solve_range_space,
    sphere,
)
from .batch import evaluate_batch, solve_batch

__all__ = [
    "ConicAnalysisSettings",
    "ConstrainedSettings",
    "ConstrainedSolution",
    "ContactMode",
    "Epsilon",
    "ForceClosure",
    "Grasp",
    "GraspQuality",
    "HandDimensions",
    "Model",
    "MonitorReport",
    "Primitive",
    "Shape",
    "Solution",
    "Status",
    "box",
    "capsule",
    "cylinder",
    "decompose_forces",
    "epsilon",
    "evaluate_batch",
    "force_closure",
    "forward_kinematics",
    "grasp_quality",
    "hand_contacts",
    "max_contacts",
    "monitor",
    "solve_batch",
    "solve_constrained",
    "solve_kkt",
    "solve_range_space",
    "sphere",
]
