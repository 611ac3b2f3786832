"""Scene model and readers/writers (Inria PLY, cameras.json, COLMAP, transforms.json)."""

from .model import Camera, GaussianScene, rgb_to_sh_dc, sh_degree_of

__all__ = ["Camera", "GaussianScene", "rgb_to_sh_dc", "sh_degree_of"]
