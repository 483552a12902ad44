"""Meshes drawn with fewer triangles in small images: a render context's copy of a model.

    context_model = render_meshes.simplified(model, render_meshes.face_budget(64, 64))
    # None: the model's meshes fit the budget and are drawn as they are

For images up to `rendering.SMALL_FRAME` pixels a side, the meshes a render context uploads
are simplified by vertex clustering to at most FACES_PER_PIXEL triangles per pixel. Vertices
are not moved, so silhouettes stay within a grid cell of where they were. Only what is drawn
changes: the scene is still built from the model; the simulation's meshes are never touched.
"""

from __future__ import annotations

import copy
import hashlib
import threading

import mujoco
import numpy as np

# Triangles per pixel of the image the meshes may have in all, for small images; None draws
# every mesh as it is.
FACES_PER_PIXEL: int | None = 8
# A mesh keeps at least this many triangles.
_MIN_FACES = 32
# Refinements of the grid size per mesh (each one clustering of its vertices).
_SEARCH_STEPS = 4
_cache: dict[tuple[bytes, int], dict[int, tuple[np.ndarray, np.ndarray]]] = {}
_cache_lock = threading.Lock()
_CACHED_MODELS = 8


def face_budget(height: int, width: int) -> int | None:
    """The number of mesh triangles a model may draw in an image of `height` x `width`
    (None: no limit)."""
    if FACES_PER_PIXEL is None:
        return None
    return FACES_PER_PIXEL * int(height) * int(width)


def simplified(model: mujoco.MjModel, budget: int) -> mujoco.MjModel | None:
    """A copy of `model` whose meshes have at most about `budget` triangles in all (each mesh
    its share, at least a few dozen), or None when `model`'s meshes have no more than that.
    Only the copy's triangle lists change (`mesh_face`, `mesh_facenormal`,
    `mesh_facetexcoord`, `mesh_facenum`); `model` is not changed.

    The render context is made from the copy, which is dropped once the context holds the
    triangles. The scene is still built from the model itself (colours, sizes and poses
    written at run time show), and the simulation's meshes (collisions, rays, sensors) are
    never touched. Results are kept by the meshes' content, so the renderers of many
    environments or of a recompile reuse them."""
    total = int(model.mesh_facenum.sum())
    if total <= budget:
        return None
    faces_by_mesh = _simplified_faces(model, budget / total)
    copied = copy.copy(model)
    for mesh, (kept, faces) in faces_by_mesh.items():
        start, count = int(model.mesh_faceadr[mesh]), int(model.mesh_facenum[mesh])
        end = start + len(faces)
        copied.mesh_face[start:end] = faces
        copied.mesh_facenormal[start:end] = model.mesh_facenormal[start : start + count][kept]
        copied.mesh_facetexcoord[start:end] = model.mesh_facetexcoord[start : start + count][kept]
        copied.mesh_facenum[mesh] = len(faces)
    return copied


def _simplified_faces(
    model: mujoco.MjModel, ratio: float
) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """For each mesh with more than its share of triangles: the indices of the triangles kept
    (within the mesh) and their new vertex indices; cached by the meshes' content."""
    key = (_meshes_digest(model), int(ratio * 1e9))
    with _cache_lock:
        found = _cache.get(key)
    if found is not None:
        return found
    result = {}
    for mesh in range(model.nmesh):
        count = int(model.mesh_facenum[mesh])
        target = max(_MIN_FACES, int(count * ratio))
        if count <= target:
            continue
        vertices = model.mesh_vertadr[mesh] + np.arange(model.mesh_vertnum[mesh])
        start = int(model.mesh_faceadr[mesh])
        faces = model.mesh_face[start : start + count].astype(np.int64)
        result[mesh] = _clustered_to(model.mesh_vert[vertices], faces, target)
    with _cache_lock:
        if len(_cache) >= _CACHED_MODELS:
            _cache.pop(next(iter(_cache)))
        _cache[key] = result
    return result


def _meshes_digest(model: mujoco.MjModel) -> bytes:
    """A digest of everything the simplified triangles depend on."""
    digest = hashlib.blake2b(digest_size=16)
    for array in (model.mesh_vertadr, model.mesh_vertnum, model.mesh_faceadr,
                  model.mesh_facenum, model.mesh_vert, model.mesh_face):  # fmt: skip
        digest.update(np.ascontiguousarray(array).data)
    return digest.digest()


def _clustered_to(
    vertices: np.ndarray, faces: np.ndarray, target: int
) -> tuple[np.ndarray, np.ndarray]:
    """The finest clustering found in `_SEARCH_STEPS` tries that leaves at most `target`
    triangles (kept indices, new faces). Triangles grow about as the square of the grid's
    cells a side, which each try's next size uses."""
    cells = max(2, int(np.sqrt(target)))
    best: tuple[np.ndarray, np.ndarray] | None = None
    for _ in range(_SEARCH_STEPS):
        kept, clustered = _clustered(vertices, faces, cells)
        found = len(clustered)
        if found <= target and (best is None or found > len(best[1])):
            best = (kept, clustered)
            if found >= 0.8 * target:
                break
        estimate = int(cells * np.sqrt(target / max(found, 1)))
        cells = max(cells + 1, estimate) if found <= target else max(1, min(cells - 1, estimate))
    while best is None:  # each try had too many: halve until it fits
        cells = max(1, cells // 2)
        kept, clustered = _clustered(vertices, faces, cells)
        if len(clustered) <= target or cells == 1:
            best = (kept, clustered)
    return best


def _clustered(
    vertices: np.ndarray, faces: np.ndarray, cells: int
) -> tuple[np.ndarray, np.ndarray]:
    """`faces` with each vertex replaced by the first vertex of its grid cell (`cells` a side
    over the longest extent), without collapsed and repeated triangles: (indices of the kept
    triangles, their faces). A triangle and its reverse are both kept (the two sides).
    Vertices are not moved (the kept triangles use the mesh's own vertices and normals), so
    silhouettes stay where they were, within a grid cell, a fraction of a pixel at the
    sizes this is used for."""
    low = vertices.min(axis=0)
    extent = float((vertices.max(axis=0) - low).max()) or 1.0
    grid = np.minimum((vertices - low) * (cells / extent), cells - 1).astype(np.int64)
    cell = (grid[:, 0] * cells + grid[:, 1]) * cells + grid[:, 2]
    _, first, inverse = np.unique(cell, return_index=True, return_inverse=True)
    clustered = first[inverse][faces]
    a, b, c = clustered.T
    kept = np.flatnonzero((a != b) & (b != c) & (a != c))
    clustered = clustered[kept]
    # The same triangle, same orientation, is the same rotation starting at its least index.
    rotation = np.argmin(clustered, axis=1)[:, None] + np.arange(3)
    rotated = np.take_along_axis(clustered, rotation % 3, axis=1)
    size = len(vertices)
    if size < 2**21:  # three indices in one int64
        _, unique = np.unique((rotated[:, 0] * size + rotated[:, 1]) * size + rotated[:, 2],
                              return_index=True)  # fmt: skip
    else:
        _, unique = np.unique(rotated, axis=0, return_index=True)
    unique.sort()
    return kept[unique], clustered[unique].astype(np.int32)
