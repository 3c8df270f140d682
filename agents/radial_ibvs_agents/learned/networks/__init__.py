"""What a learned policy computes: its inputs, its feature extractors, its residual form.

- :mod:`~radial_ibvs_agents.learned.networks.history`: the last frames, for training and in the
  deployed policy's ``state``;
- :mod:`~radial_ibvs_agents.learned.networks.extractors`: the feature extractors (errors as
  direction and log-size, the landmarks as a set, the goal's pose); torch modules;
- :mod:`~radial_ibvs_agents.learned.networks.pose_layer`: the goal's pose from one radial image, in
  closed form;
- :mod:`~radial_ibvs_agents.learned.networks.residual`: a learned, bounded correction on top of an
  analytic policy.

This package's own module loads no torch: it names the extractors a config may ask for.
"""

__all__ = ["EXTRACTORS", "TRAIN_EXTRACTORS"]

#: a DAgger student's feature extractors, by name (classes of
#: :mod:`radial_ibvs_agents.learned.networks.extractors`)
EXTRACTORS = {
    "error_scale": "ErrorScaleExtractor",
    "landmark_set": "LandmarkSetExtractor",
    "landmark_pose": "LandmarkPoseExtractor",
}
#: the extractors a training config may name: the students' and the goal env's
TRAIN_EXTRACTORS = {**EXTRACTORS, "goal_pose": "GoalPoseExtractor"}
