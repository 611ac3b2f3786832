"""CapFrame: text-instructed camera viewpoint grounding in 3D Gaussian Splatting scenes."""

__version__ = "0.1.0"
