"""The ``detector`` segmenter: a closed-set COCO detector on ONNX Runtime, for CPU users.

The subject's name is mapped to one of the 80 COCO classes (:func:`coco_class`); in each view the
detector's best box of that class at or above the threshold is turned into a mask by SAM when
the models config has a ``sam`` entry, else by GrabCut seeded by the box and the rendered depth
(:func:`~capframe.backends.masks.grabcut_box`), then the largest contour is filled.

The ONNX model (the ``detector`` entry's ``weights``) must have one image input of fixed square
size, NHWC or NCHW with 3 channels, RGB values 0-255, and an output of shape ``[1, N, 6]``: boxes
``x0, y0, x1, y1`` in input pixels, a score and a COCO-80 class id. Images are letterboxed (an
aspect-preserving resize centred on black), as the reference CenterNet does best with.
"""

from __future__ import annotations

import difflib

import cv2
import numpy as np

from ..errors import InputError
from ..retrieve.views import VIEWS_LONG_SIDE
from ..translate.instruction import ParsedSubject
from .masks import clip_box, fill_largest_contour, grabcut_box, subject_masks
from .models import ModelSettings
from .protocols import BackendContext, SubjectMasks
from .sam import ENTRY as SAM_ENTRY
from .sam import SamBoxes
from .views import view_depth, view_image
from .weights import onnx_session

ENTRY = "detector"  # the models-config entry
SCORE_THRESHOLD = 0.3  # default box score threshold (the entry's ``threshold`` overrides it)
GRABCUT_LONG_SIDE = 512  # GrabCut's cost grows with the pixels; masks end at 160 px anyway

# The COCO-80 classes in the order of the detector's class ids.
COCO_CLASSES = tuple(
    "person,bicycle,car,motorcycle,airplane,bus,train,truck,boat,traffic light,fire hydrant,stop sign,parking meter,"
    "bench,bird,cat,dog,horse,sheep,cow,elephant,bear,zebra,giraffe,backpack,umbrella,handbag,tie,suitcase,frisbee,"
    "skis,snowboard,sports ball,kite,baseball bat,baseball glove,skateboard,surfboard,tennis racket,bottle,wine glass,"
    "cup,fork,knife,spoon,bowl,banana,apple,sandwich,orange,broccoli,carrot,hot dog,pizza,donut,cake,chair,couch,"
    "potted plant,bed,dining table,toilet,tv,laptop,mouse,remote,keyboard,cell phone,microwave,oven,toaster,sink,"
    "refrigerator,book,clock,vase,scissors,teddy bear,hair drier,toothbrush".split(",")
)

# Other names of COCO classes (lower case): common synonyms, and the nearest class for objects
# COCO has none of its own (a toy car looks like a car; COCO's only table is "dining table").
COCO_SYNONYMS = {
    "tv": ("television", "television set", "tv set", "tv monitor", "tvmonitor", "monitor", "screen"),
    "couch": ("sofa", "settee"),
    "chair": ("armchair", "easy chair", "lounge chair", "stool"),
    "cup": ("mug", "coffee mug", "coffee cup", "teacup"),
    "potted plant": ("plant", "houseplant", "pot plant", "pottedplant"),
    "vase": ("flower vase",),
    "sports ball": ("ball", "beach ball", "toy ball", "football", "soccer ball", "basketball", "tennis ball"),
    "teddy bear": ("teddy", "stuffed bear", "plush bear", "stuffed animal"),
    "refrigerator": ("fridge", "icebox"),
    "bench": ("park bench", "garden bench"),
    "car": ("toy car", "model car", "automobile"),
    "dining table": ("table", "coffee table", "dinner table", "desk", "diningtable"),
    "motorcycle": ("motorbike",),
    "airplane": ("aeroplane", "plane"),
    "bicycle": ("bike",),
    "cell phone": ("phone", "mobile phone", "cellphone", "smartphone"),
    "hair drier": ("hair dryer",),
}
COCO_ALIASES = {alias: name for name, aliases in COCO_SYNONYMS.items() for alias in aliases}


def coco_class(name: str) -> int:
    """The COCO-80 class id of a subject name (a class name or one of :data:`COCO_ALIASES`, case
    and spacing ignored); :class:`InputError` naming the closest classes otherwise."""
    key = " ".join(name.lower().replace("_", " ").replace("-", " ").split())
    key = COCO_ALIASES.get(key, key)
    if key in COCO_CLASSES:
        return COCO_CLASSES.index(key)
    vocabulary = sorted({*COCO_CLASSES, *COCO_ALIASES})
    close = [COCO_ALIASES.get(n, n) for n in difflib.get_close_matches(key, vocabulary, n=6, cutoff=0.0)]
    closest = list(dict.fromkeys(close))[:3]
    raise InputError(f"--segmenter detector: subject {name!r} is not a COCO class; the closest are {', '.join(closest)}")


def letterbox(image: np.ndarray, size: int) -> tuple[np.ndarray, float, tuple[float, float]]:
    """``image`` (H, W, 3) uint8 resized to fit ``size`` x ``size``, centred on black.

    Returns:
        (size, size, 3) float32 image (0-255), the scale and the (x, y) offset: input pixel
        ``p`` is ``(p - offset) / scale`` in the image.
    """
    H, W = image.shape[:2]
    scale = size / max(H, W)
    w, h = max(1, round(W * scale)), max(1, round(H * scale))
    ox, oy = (size - w) // 2, (size - h) // 2
    canvas = np.zeros((size, size, 3), dtype=np.float32)
    interpolation = cv2.INTER_AREA if scale < 1 else cv2.INTER_LINEAR  # area: no aliasing when shrinking a photo
    canvas[oy : oy + h, ox : ox + w] = cv2.resize(image, (w, h), interpolation=interpolation)
    return canvas, scale, (float(ox), float(oy))


class OnnxDetector:
    """A closed-set COCO detector on onnxruntime (layout in the module docstring).

    Args:
        settings: the ``detector`` entry (``weights``: the ONNX file; threshold, threads).
    """

    def __init__(self, settings: ModelSettings):
        self.session = onnx_session(ENTRY, settings)
        self.threshold = SCORE_THRESHOLD if settings.threshold is None else settings.threshold
        source = settings.weights
        inputs = self.session.get_inputs()
        shape = list(inputs[0].shape) if len(inputs) == 1 else []
        layouts = {"NHWC": (shape[1:3], shape[3:]), "NCHW": (shape[2:4], shape[1:2])} if len(shape) == 4 else {}
        found = [k for k, (hw, c) in layouts.items() if c == [3] and len(set(hw)) == 1 and isinstance(hw[0], int)]
        if not found:
            raise InputError(
                f"the detector's input is {[(i.name, i.shape) for i in inputs]}; expected one image [1, S, S, 3] or [1, 3, S, S]",
                source=source,
            )
        self.input_name, self.layout = inputs[0].name, found[0]
        self.size = int(layouts[self.layout][0][0])
        outputs = [o for o in self.session.get_outputs() if len(o.shape) == 3 and o.shape[2] == 6]
        if not outputs:
            raise InputError(
                f"the detector has no [1, N, 6] output (x0, y0, x1, y1, score, class); its outputs are "
                f"{[(o.name, o.shape) for o in self.session.get_outputs()]}",
                source=source,
            )
        self.output_name = outputs[0].name

    def detect(self, image: np.ndarray) -> np.ndarray:
        """(N, 6) detections of ``image`` (H, W, 3) uint8 RGB: x0, y0, x1, y1 in its pixels,
        score, class id; those scoring at or above the threshold, best first."""
        canvas, scale, (ox, oy) = letterbox(image, self.size)
        batch = canvas[None] if self.layout == "NHWC" else canvas.transpose(2, 0, 1)[None]
        detections = np.asarray(self.session.run([self.output_name], {self.input_name: batch})[0][0], dtype=np.float64)
        detections = detections[detections[:, 4] >= self.threshold]
        detections[:, [0, 2]] = (detections[:, [0, 2]] - ox) / scale
        detections[:, [1, 3]] = (detections[:, [1, 3]] - oy) / scale
        return detections[np.argsort(-detections[:, 4], kind="stable")]

    def best_box(self, image: np.ndarray, class_id: int) -> np.ndarray | None:
        """The (4,) box of class ``class_id`` with the highest score in ``image``, or None."""
        detections = self.detect(image)
        detections = detections[detections[:, 5].round() == class_id]
        return clip_box(detections[0, :4], *image.shape[:2]) if len(detections) else None


class DetectorSegmenter:
    """Closed-set detector boxes, masks by SAM or GrabCut (the :class:`Segmenter` protocol).

    Args:
        context: the job's context; its models config needs ``detector`` and may have ``sam``.
    """

    def __init__(self, context: BackendContext):
        self.context = context
        self.detector = OnnxDetector(context.models.settings(ENTRY))
        self.sam = SamBoxes(context.models.settings(SAM_ENTRY)) if SAM_ENTRY in context.models.entries else None

    def _grabcut(self, view: int, image: np.ndarray, box: np.ndarray) -> np.ndarray:
        """(H, W) bool mask of ``box`` in view ``view``'s image (H, W, 3), by GrabCut at a long
        side of at most :data:`GRABCUT_LONG_SIDE`."""
        H, W = image.shape[:2]
        camera = self.context.scene.cameras[view].resized(W, H).with_long_side(min(GRABCUT_LONG_SIDE, max(H, W)))
        h, w = camera.height, camera.width
        small = cv2.resize(image, (w, h), interpolation=cv2.INTER_AREA)
        depth = view_depth(self.context, view, h, w)
        mask = grabcut_box(small, depth, box * [w / W, h / H, w / W, h / H], float(np.sqrt(camera.K[0, 0] * camera.K[1, 1])))
        return fill_largest_contour(mask)

    def segment(self, subject: ParsedSubject, view_indices: list[int]) -> SubjectMasks:
        """The subject's masks at the association's measurement resolution, in the views where
        the detector found its class."""
        class_id = coco_class(subject.name)
        images = {v: view_image(self.context, v) for v in view_indices}
        boxes = {v: box for v in view_indices if (box := self.detector.best_box(images[v], class_id)) is not None}
        if self.sam is not None:
            masks = {v: m[0] for v, m in self.sam.masks(images, {v: b[None] for v, b in boxes.items()}).items()}
        else:
            masks = {v: self._grabcut(v, images[v], box) for v, box in boxes.items()}
        size = self.context.scene.cameras[view_indices[0]].with_long_side(VIEWS_LONG_SIDE)
        return subject_masks(view_indices, masks, size.height, size.width)
