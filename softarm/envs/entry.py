"""What `gymnasium.make_vec("softarm/...-v0", num_envs=N)` builds: the NumPy vector env, or, given `device=`, the
one whose tensors stay on that device (torch is imported only then)."""

from typing import Any, Optional

from gymnasium.vector import VectorEnv


def vector_env(num_envs: int = 1, device: Optional[str] = None, **kwargs: Any) -> VectorEnv:
    if device is None:
        from softarm.envs.vector import SoftArmVectorEnv

        return SoftArmVectorEnv(num_envs, **kwargs)
    from softarm.envs.device_vector import DeviceVectorEnv

    return DeviceVectorEnv(num_envs, device=device, **kwargs)
