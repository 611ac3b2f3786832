"""The paper's baselines (§6 and supplement): the same Parse / Retrieve / Translate as CapFrame,
another pose search.

* **IVS** (interpolation-based viewpoint search): the top ``L = min(13, N)`` retrieved training
  views plus three interpolated poses per pair of them, best candidate by the scorer;
* **SVS** (sampling-based viewpoint search): as many poses sampled on a sphere around the
  subjects, looking at their centre, best candidate by the scorer;
* **SplaTraj-style**: one pose optimised from the top retrieved view for mask centring, mask
  area and uprightness only;
* **ChatCam-style**: one pose optimised from the training view with the best image-text score
  for the differentiable image-text score of its render (``--diff-scorer``, model tier only) and
  uprightness.

The scorer of IVS and SVS is the paper's text-image similarity (FG-CLIP) in the model tier; the
embedded tier scores by Question-Evaluation on label renders (the oracle image-text scorer).
"""

from .candidates import interpolate_pose, ivs_candidates, svs_candidates
from .chatcam import ChatCamConfig, chatcam_pose
from .run import METHODS, BaselineOptions, run_baseline
from .splatraj import SplaTrajConfig, splatraj_pose

__all__ = [
    "METHODS",
    "BaselineOptions",
    "ChatCamConfig",
    "SplaTrajConfig",
    "chatcam_pose",
    "interpolate_pose",
    "ivs_candidates",
    "run_baseline",
    "splatraj_pose",
    "svs_candidates",
]
