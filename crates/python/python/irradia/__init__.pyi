"""Type stubs of the irradia package (docs/python.md has the guide)."""

import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
#: geometry_ids / primitive_ids of a ray that hit nothing (Open3D's INVALID_ID).
INVALID_ID: int

PathLike = Union[str, os.PathLike]
Vec3 = Union[Sequence[float], npt.NDArray[np.floating]]
Color = Union[float, Vec3]
Progress = Union[bool, Callable[[int, Optional[int]], Any], None]

class IrradiaError(ValueError):
    """Bad input (a scene file, an option, an unknown name) with the message the
    `irradia` command prints; scene errors name file, line and field."""

class Scene:
    """A validated scene; make one with load, load_dict or builtin."""

    width: int
    """Image width in pixels (1 to 65536)."""
    height: int
    """Image height in pixels."""
    spp: int
    """Samples per pixel."""
    max_depth: int
    """The deepest ray, camera rays being depth 1."""
    integrator: str
    """"whitted", "path" (settable) or "direct"."""
    @property
    def source(self) -> Optional[str]:
        """The file the scene came from ("builtin:NAME.toml" for built-ins)."""
    @property
    def warnings(self) -> List[str]:
        """Features of an imported file read but not rendered."""
    @property
    def camera(self) -> Dict[str, Any]:
        """eye, look_at, up, projection, and fov (degrees) or height."""
    @property
    def objects(self) -> List[Dict[str, Any]]:
        """name and material index of each object, in id order."""
    @property
    def materials(self) -> List[Dict[str, Any]]:
        """A copy of the materials (change them with set_material)."""
    @property
    def lights(self) -> List[Dict[str, Any]]:
        """A copy of the lights, each with its "type" (change them with set_light)."""
    @property
    def last_render(self) -> Optional[Dict[str, Any]]:
        """samples, rays, seconds, stop, relative_error, statistics of the last render."""
    def set_camera(
        self,
        *,
        eye: Optional[Vec3] = None,
        look_at: Optional[Vec3] = None,
        up: Optional[Vec3] = None,
        fov: Optional[float] = None,
    ) -> None:
        """Moves the camera; arguments left out keep their value."""
    def set_material(self, key: Union[int, str], **fields: Any) -> None:
        """Changes a material by name or index: color, ambient, diffuse, specular,
        shininess, reflection, transmission, ior, fresnel, emission."""
    def set_light(self, index: int, **fields: Any) -> None:
        """Changes a light: position, intensity, direction, irradiance, radiance,
        corner, center, radius (those its type has)."""
    def render(
        self,
        *,
        integrator: Optional[str] = None,
        spp: Optional[int] = None,
        threads: Optional[int] = None,
        aovs: Union[str, Sequence[str], None] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        max_depth: Optional[int] = None,
        tile_size: int = 32,
        time: Optional[float] = None,
        target_error: Optional[float] = None,
        seed: Optional[int] = None,
        checkpoint: Optional[PathLike] = None,
        resume: Optional[PathLike] = None,
        progress: Progress = None,
    ) -> Union[npt.NDArray[np.float32], Dict[str, np.ndarray]]:
        """Renders the scene as `irradia render` does, with its option names and
        defaults (None keeps the scene's value; the scene is not changed).

        Returns linear radiance, float32 of shape (height, width, 3). With `aovs`
        (names of `--aov`: "depth", "normal", "object-id", "ray-depth"), a dict of
        "color" and each AOV: depth float32 (h, w) (inf for the background), normal
        float32 (h, w, 3), object-id and ray-depth int32 (h, w).

        `progress`: a callable (done, total) called on the calling thread with
        pixel-samples (total None under a time or error budget), or True for a tqdm
        bar. Ctrl-C raises KeyboardInterrupt after the tiles in flight finish; an
        exception from the callback stops the render the same way.
        """
    def trace_pixel(
        self,
        x: int,
        y: int,
        *,
        sample: int = 0,
        integrator: Optional[str] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        max_depth: Optional[int] = None,
    ) -> Dict[str, Any]:
        """The ray tree of pixel (x, y): {"pixel", "sample", "radiance", "rays",
        "tree"}, each node {"kind", "depth", "origin", "direction", "hit", "local",
        "weight", "radiance", "contribution", "children"} (as `irradia trace-pixel
        --format json`)."""
    def cast_rays(
        self,
        rays: npt.NDArray[np.float32],
        directions: Optional[npt.NDArray[np.float32]] = None,
        *,
        t_max: Optional[float] = None,
        threads: Optional[int] = None,
    ) -> Dict[str, np.ndarray]:
        """Closest hits of float32 rays (..., 6) or origins and directions (..., 3):
        t_hit (...) float32 (inf: miss; in units of the direction), geometry_ids and
        primitive_ids (...) uint32 (INVALID_ID: miss), primitive_uvs (..., 2),
        primitive_normals (..., 3) float32 (Open3D's RaycastingScene.cast_rays)."""

def load(path: PathLike, *, defines: Optional[Mapping[str, str]] = None, strict: bool = False) -> Scene:
    """A scene file of any format `irradia render` reads: .toml, .json, Mitsuba .xml,
    pbrt .pbrt, .obj, .ply, .gltf/.glb. `defines` sets Mitsuba's $parameters;
    `strict` refuses features read but not rendered."""

def load_dict(d: Mapping[str, Any], base_dir: Optional[PathLike] = None) -> Scene:
    """A scene from a dict in the scene-file schema (docs/scene-format.md)."""

def builtin(name: str) -> Scene:
    """A built-in scene by name (see builtins())."""

def builtins() -> List[Tuple[str, str]]:
    """(name, description) of every built-in scene."""

def read_image(path: PathLike) -> npt.NDArray[np.float32]:
    """A PNG, EXR, PFM or .hdr file as linear float32 (h, w, 3)."""

def write_image(path: PathLike, image: npt.ArrayLike) -> None:
    """Writes .png (sRGB 8-bit), .exr or .pfm (linear float) atomically from an
    (h, w), (h, w, 1) or (h, w, 3) array: floats are linear, uint8 is sRGB."""

def form_factor(case: str, **params: float) -> float:
    """A closed form of the lecture's catalogue, as `irradia formfactor CASE --p v`."""

def form_factor_cases() -> List[Dict[str, Any]]:
    """name, geometry and params (name -> meaning) of every closed form."""

def radiosity(
    scene: Union[Scene, PathLike, None] = None,
    *,
    builtin: Optional[str] = None,
    form_factors: str = "hemicube",
    solver: str = "gauss-seidel",
    max_element_area: Optional[float] = None,
    elements: int = 1000,
    element_limit: int = 2000000,
    hemicube_resolution: int = 128,
    hemisphere_resolution: int = 64,
    rays: int = 16,
    samples: int = 16,
    visibility_samples: int = 4,
    tolerance: float = 1e-6,
    max_iterations: int = 10000,
    bf_epsilon: float = 1e-4,
    link_rays: int = 4,
    adaptive: int = 0,
    seed: int = 1,
    closed: bool = False,
    compare_solvers: bool = False,
    return_form_factors: bool = False,
) -> Dict[str, Any]:
    """Solves a scene by radiosity as `irradia radiosity` does (same options and
    defaults; no scene and no builtin: the measured Cornell box).

    Returns radiosity (n, 3), display_radiosity (n, 3), area (n,), centroid (n, 3),
    surface (n,) (input polygon of each element), residuals (the chosen solver's
    relative residual per iteration), residual, histories (solver -> residuals; every
    matrix solver with compare_solvers), form_factors (n, n) with
    return_form_factors (matrix methods), diagnostics, timings, notes, warnings."""

def composite(
    color: np.ndarray,
    depth: Optional[npt.NDArray[np.float32]] = None,
    strategy: str = "binary-swap",
    comm: Any = None,
    *,
    op: Optional[str] = None,
    order: Optional[Sequence[int]] = None,
    root: int = 0,
    rle: bool = True,
    timeout: float = 60.0,
    tiles: Optional[Sequence[Tuple[int, int, int, int, int]]] = None,
) -> Any:
    """Sort-last compositing of premultiplied RGBA (uint8 or float32) with depth:
    over an mpi4py communicator one layer per rank onto `root` (others get None), or
    without one a stack (n, h, w, 4) serially. op "depth" or "over" (in `order`).
    With `tiles` ((rank, x, y, width, height) each) every display rank gets its tile
    (serially: a list of every tile's (color, depth)). Returns (color, depth) or None."""

def display_grid(width: int, height: int, columns: int, rows: int, overlap: int = 0) -> List[Tuple[int, int, int, int, int]]:
    """The tiles (rank, x, y, width, height) of a columns x rows display wall over a
    width x height image, ranks row by row, each widened by `overlap` pixels."""

def mpi_available() -> bool:
    """Whether this build composites over MPI (cargo feature mpi)."""
