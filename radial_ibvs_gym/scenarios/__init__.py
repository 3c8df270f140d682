"""Scenarios: the rooms, landmarks, cameras and parking tasks of the environments."""

from radial_ibvs_gym.scenarios.scenario import Episode, Scenario, load_scenario
from radial_ibvs_gym.scenarios.spec import (
    PoseRange,
    RandomLandmarks,
    RandomObstacles,
    RandomRoom,
    ScenarioConfig,
    TaskSpec,
)

__all__ = [
    "Episode",
    "PoseRange",
    "RandomLandmarks",
    "RandomObstacles",
    "RandomRoom",
    "Scenario",
    "ScenarioConfig",
    "TaskSpec",
    "load_scenario",
]
