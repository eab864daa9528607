"""Control environments: the arm with muscles as Gymnasium envs, one arm (`Env`) or many in one kernel launch
(a native `VectorEnv`), registered on import (README, Control):

    import gymnasium, softarm.envs
    env = gymnasium.make("softarm/Reach-v0")
    envs = gymnasium.make_vec("softarm/Reach-v0", num_envs=256)
    envs = gymnasium.make_vec("softarm/Reach-v0", num_envs=16_384, device="cuda")  # torch tensors on the GPU

Tasks: Reach, Track, Hold (softarm.envs.tasks); observations: softarm.envs.observations.
"""

from gymnasium.envs.registration import register, registry

from softarm.envs.tasks import TASKS

IDS = {name: f"softarm/{name.capitalize()}-v0" for name in TASKS}

for _name, _id in IDS.items():
    if _id not in registry:
        register(id=_id, entry_point="softarm.envs.single:SoftArmEnv",
                 vector_entry_point="softarm.envs.entry:vector_env", kwargs={"task": _name})

__all__ = ["IDS"]
