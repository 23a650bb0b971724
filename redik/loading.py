"""Loading robot description files (MJCF, URDF) into MuJoCo, ready for kinematics.

MuJoCo reads both formats itself (:meth:`mujoco.MjSpec.from_file`); this module fixes what
stops real-world URDFs from loading or from being useful for inverse kinematics:

* **Mesh paths.** URDFs name meshes ``package://<package>/<path>`` (ROS), ``file://<path>``
  or relative to the URDF file. Each mesh is resolved to an absolute path by trying, in order,
  the folders in ``package_paths``, the entries of ``ROS_PACKAGE_PATH`` and the ``share``
  folders of ``AMENT_PREFIX_PATH``, then the model file's own folder and every folder above it
  (so a package installed as ``…/share/<package>/`` is found from any file inside it). For a
  folder ``F`` the candidates of ``package://pkg/rest`` are ``F/pkg/rest`` and, when ``F`` is
  itself named ``pkg``, ``F/rest``; a relative path ``rest`` is tried against the model's folder
  (and its ``meshdir``) first. A mesh that is found nowhere raises :class:`ModelError` naming
  the folders searched. ``meshes=False`` drops every mesh geom instead: a kinematics-only model
  that needs no mesh file at all (and loads faster).
* **Mesh formats.** MuJoCo decodes STL, OBJ and MSH. Collision meshes in another format
  (COLLADA ``.dae`` is common) are dropped with a :class:`ModelWarning` that lists them.
  Visual geoms are discarded by MuJoCo's URDF import anyway (``discardvisual``).
* **Fixed links.** MuJoCo's URDF import fuses links attached by fixed joints into their parent
  (``<compiler fusestatic="true"/>``), so tool flanges and hands (``tool0``, ``ee_link``,
  ``panda_hand``) vanish. They are kept as jointless bodies here (``fusestatic=False``), so
  every URDF link is a frame, at the URDF link frame.
* **Inertia.** Kinematic URDFs often omit inertias and CAD exports break the triangle
  inequality of principal moments; mass and inertia are bounded from below
  (``boundmass``/``boundinertia``) and, for URDF, balanced (``balanceinertia``). Neither
  changes a valid link nor any kinematics.
* **Floating base.** MuJoCo's URDF import fixes the root link to the world. With
  ``floating_base=True`` a free joint named ``floating_base`` is added to the root body (its
  ``qpos`` is ``(x, y, z, qw, qx, qy, qz)``, starting at the root's URDF pose), as legged robots
  and humanoids need.

URDF ``continuous`` joints become unlimited hinges and ``mimic`` joints equality constraints
(MuJoCo's own import); MJCF files keep their keyframes, sites, includes and asset paths, which
MuJoCo resolves relative to the file.

Reference: URDF specification, https://wiki.ros.org/urdf/XML; MuJoCo XML reference,
``compiler`` element (``fusestatic``, ``discardvisual``, ``strippath``, ``balanceinertia``).
"""

from __future__ import annotations

import dataclasses
import difflib
import io
import os
import warnings
import xml.etree.ElementTree as ElementTree
from collections.abc import Iterable, Sequence
from pathlib import Path

import mujoco
import numpy as np

from .exceptions import ModelError, ModelWarning, UnknownFrame

# Mesh formats MuJoCo decodes without a plugin; other extensions are probed once per run.
_DECODED_MESH_FORMATS = {".stl", ".obj", ".msh"}
_probed_mesh_formats: dict[str, bool] = {}

_URI_SCHEMES = ("package://", "model://")

FLOATING_BASE_JOINT = "floating_base"


@dataclasses.dataclass(frozen=True)
class LoadOptions:
    """How a model file is loaded; every field is an argument of :func:`load_spec`."""

    meshes: bool = True
    package_paths: tuple[Path, ...] = ()
    floating_base: bool = False
    keep_fixed_links: bool = True


def load_spec(
    source: str | Path,
    *,
    meshes: bool = True,
    package_paths: Sequence[str | Path] | str | Path | None = None,
    floating_base: bool = False,
    keep_fixed_links: bool = True,
) -> mujoco.MjSpec:
    """Read an MJCF or URDF file into an editable :class:`mujoco.MjSpec` (see the module notes).

    Args:
        source: Path of a ``.urdf`` or MJCF (``.xml``/``.mjcf``) file; a ``.xml`` file whose
            root element is ``<robot>`` is read as URDF.
        meshes: Resolve and load mesh files (True), or drop every mesh geom for a
            kinematics-only model (False).
        package_paths: Folders searched first for ``package://`` and relative mesh paths:
            folders that contain ROS packages, or a package folder itself.
        floating_base: Add a free joint to the root body (URDF, or MJCF with one root body).
        keep_fixed_links: Keep links attached by fixed joints as bodies (URDF only).

    Raises:
        ModelError: the file is missing, unreadable, a mesh cannot be found, or
            ``floating_base`` cannot be applied.
    """
    path = Path(source)
    if not path.is_file():
        raise ModelError(f"robot file not found: {str(path)!r}")
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as error:
        raise ModelError(f"cannot read {str(path)!r}: {error}") from None
    urdf = path.suffix.lower() == ".urdf" or _root_tag(text) == "robot"
    try:
        spec = mujoco.MjSpec.from_file(str(path))
    except ValueError as error:
        raise ModelError(f"MuJoCo could not load {str(path)!r}: {error}") from None
    options = _options(meshes, package_paths, floating_base, keep_fixed_links)
    _prepare(spec, urdf, path.resolve().parent, str(path), options)
    return spec


def load_spec_from_string(
    xml: str,
    *,
    directory: str | Path | None = None,
    meshes: bool = True,
    package_paths: Sequence[str | Path] | str | Path | None = None,
    floating_base: bool = False,
    keep_fixed_links: bool = True,
) -> mujoco.MjSpec:
    """:func:`load_spec` for an MJCF or URDF string; relative paths start at ``directory``.

    ``directory`` defaults to the current working directory.
    """
    if not isinstance(xml, str):
        raise ModelError(f"the model must be an XML string, got {type(xml).__name__}")
    urdf = _root_tag(xml) == "robot"
    try:
        spec = mujoco.MjSpec.from_string(xml)
    except ValueError as error:
        raise ModelError(f"MuJoCo could not parse the model: {error}") from None
    base = Path(directory).resolve() if directory is not None else Path.cwd()
    # Assets are then named relative to ``directory``, as they would be for a file there.
    spec.modelfiledir = str(base) + os.sep
    options = _options(meshes, package_paths, floating_base, keep_fixed_links)
    _prepare(spec, urdf, base, "the model string", options)
    return spec


def load_model(source: str | Path, **options) -> mujoco.MjModel:
    """:func:`load_spec` then :func:`compile_spec`: a compiled :class:`mujoco.MjModel`."""
    return compile_spec(load_spec(source, **options), str(source))


def compile_spec(spec: mujoco.MjSpec, source: str = "the model") -> mujoco.MjModel:
    """Compile a spec; links without inertia (common in URDF) get a tiny mass, not an error.

    Kinematic URDFs routinely omit inertias, which MuJoCo rejects for moving bodies. Bounding
    mass (1e-6 kg) and inertia (1e-12 kg m²) from below changes nothing for links that have
    them.

    Raises:
        ModelError: MuJoCo cannot compile the spec; the message is MuJoCo's.
    """
    if spec.compiler.boundmass == 0.0 and spec.compiler.boundinertia == 0.0:
        spec.compiler.boundmass = 1e-6
        spec.compiler.boundinertia = 1e-12
    try:
        return spec.compile()
    except ValueError as error:
        raise ModelError(f"MuJoCo could not compile {source}: {error}") from None


def search_folders(
    package_paths: Sequence[str | Path] | str | Path | None = None,
    model_directory: str | Path | None = None,
) -> list[Path]:
    """The folders searched for meshes, in order (see the module notes); existing ones only."""
    folders: list[Path] = [Path(p).expanduser() for p in _as_paths(package_paths)]
    folders += [Path(p) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
    folders += [
        Path(p) / "share" for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p
    ]
    if model_directory is not None:
        start = Path(model_directory).resolve()
        folders += [start, *start.parents]
    unique: dict[Path, None] = {}
    for folder in folders:
        if folder.is_dir():
            unique.setdefault(folder.resolve(), None)
    return list(unique)


def resolve_mesh_path(
    name: str,
    model_directory: str | Path,
    folders: Iterable[Path],
    *,
    meshdir: str = "",
    strip: bool = False,
) -> Path | None:
    """The file a URDF/MJCF mesh reference names, or None when no candidate exists.

    ``name`` is ``package://pkg/rest``, ``model://pkg/rest``, ``file://path``, an absolute
    path or a path relative to ``model_directory`` (after ``meshdir``; only the file name when
    ``strip``, as MuJoCo's ``strippath`` does).
    """
    model_directory = Path(model_directory)
    for scheme in _URI_SCHEMES:
        if name.startswith(scheme):
            package, _, rest = name[len(scheme) :].partition("/")
            candidates = []
            for folder in folders:
                candidates.append(folder / package / rest)
                if folder.name == package:
                    candidates.append(folder / rest)
            return _first_file(candidates)
    if name.startswith("file://"):
        name = name[len("file://") :]
    relative = Path(name)
    if relative.is_absolute():
        return relative if relative.is_file() else None
    if strip:
        relative = Path(relative.name)
    candidates = []
    if meshdir:
        candidates.append(model_directory / meshdir / relative)
    candidates.append(model_directory / relative)
    candidates += [folder / relative for folder in folders]
    return _first_file(candidates)


def unknown_frame(model: mujoco.MjModel, name: str, label: str = "the model") -> UnknownFrame:
    """The :class:`UnknownFrame` for a frame name that names no site or body of ``model``.

    The message gives the closest names (:func:`difflib.get_close_matches`) and lists every
    site and body; a geom of that name is pointed out (geoms are not frames: add a site).
    """
    sites = object_names(model, mujoco.mjtObj.mjOBJ_SITE)
    bodies = object_names(model, mujoco.mjtObj.mjOBJ_BODY)
    close = difflib.get_close_matches(str(name), sites + bodies, n=5, cutoff=0.5)
    parts = [f"no site or body named {name!r} in {label}"]
    if close:
        parts.append(f"did you mean {', '.join(map(repr, close))}?")
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, str(name)) >= 0:
        parts.append(f"{name!r} is a geom, which is not a frame: add a site at it, or use its body")
    parts.append(f"sites: {sites}; bodies: {bodies}")
    return UnknownFrame("; ".join(parts))


def object_names(model: mujoco.MjModel, obj: mujoco.mjtObj) -> list[str]:
    """Names of the model's objects of one type (``mjOBJ_SITE``, ``mjOBJ_BODY``, …), in order."""
    count = {
        mujoco.mjtObj.mjOBJ_SITE: model.nsite,
        mujoco.mjtObj.mjOBJ_BODY: model.nbody,
        mujoco.mjtObj.mjOBJ_GEOM: model.ngeom,
        mujoco.mjtObj.mjOBJ_JOINT: model.njnt,
    }[obj]
    names = (mujoco.mj_id2name(model, obj, i) for i in range(count))
    return [n for n in names if n]


# --------------------------------------------------------------------------------------
# Internals


def _options(meshes, package_paths, floating_base, keep_fixed_links) -> LoadOptions:
    for label, value in (
        ("meshes", meshes),
        ("floating_base", floating_base),
        ("keep_fixed_links", keep_fixed_links),
    ):
        if not isinstance(value, bool):
            raise ModelError(f"{label} must be True or False, got {value!r}")
    return LoadOptions(
        meshes=meshes,
        package_paths=tuple(Path(p).expanduser() for p in _as_paths(package_paths)),
        floating_base=floating_base,
        keep_fixed_links=keep_fixed_links,
    )


def _as_paths(paths: Sequence[str | Path] | str | Path | None) -> list[str | Path]:
    if paths is None:
        return []
    if isinstance(paths, (str, Path)):
        return [paths]
    return list(paths)


def _root_tag(text: str) -> str | None:
    """The tag of the document's root element (``robot`` for URDF, ``mujoco`` for MJCF)."""
    try:
        for _, element in ElementTree.iterparse(io.StringIO(text), events=("start",)):
            return element.tag
    except ElementTree.ParseError:
        return None  # MuJoCo's own parser reports the error with a line number
    return None


def _prepare(
    spec: mujoco.MjSpec, urdf: bool, directory: Path, source: str, options: LoadOptions
) -> None:
    if urdf:
        spec.compiler.fusestatic = not options.keep_fixed_links
        spec.compiler.balanceinertia = True
        _repair_inertias(spec, source)
    if not options.meshes:
        _drop_meshes(spec, spec.meshes)
    else:
        _resolve_meshes(spec, urdf, directory, source, options.package_paths)
    if options.floating_base:
        _add_floating_base(spec, source)


def _repair_inertias(spec: mujoco.MjSpec, source: str) -> None:
    """Make indefinite URDF inertia tensors positive definite (MuJoCo rejects them).

    The symmetric tensor ``I = V diag(λ) Vᵀ`` becomes ``V diag(max(λ, ε)) Vᵀ`` with
    ``ε = max(10⁻¹², 10⁻³ max λ)``: the nearest positive-definite tensor with the same principal
    axes. Such tensors appear in CAD exports of tiny parts; kinematics never reads them.
    """
    repaired = []
    for body in spec.bodies:
        full = np.asarray(body.fullinertia, dtype=float)
        if not np.all(np.isfinite(full)):
            continue  # diagonal inertia given (or none): MuJoCo checks it, balanceinertia fixes
        xx, yy, zz, xy, xz, yz = full
        tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        eigenvalues, axes = np.linalg.eigh(tensor)
        if eigenvalues[0] > 0.0:
            continue
        floor = max(1e-12, 1e-3 * float(eigenvalues[-1]))
        tensor = axes @ np.diag(np.maximum(eigenvalues, floor)) @ axes.T
        body.fullinertia = [*np.diag(tensor), tensor[0, 1], tensor[0, 2], tensor[1, 2]]
        repaired.append(body.name)
    if repaired:
        warnings.warn(
            f"{source}: the inertia tensors of links {repaired} are not positive definite; "
            "replaced by the nearest positive-definite tensor with the same principal axes",
            ModelWarning,
            stacklevel=5,
        )


def _users(spec: mujoco.MjSpec) -> dict[str, list[mujoco.MjsGeom]]:
    users: dict[str, list] = {}
    for geom in spec.geoms:
        if geom.type == mujoco.mjtGeom.mjGEOM_MESH or geom.meshname:
            users.setdefault(geom.meshname, []).append(geom)
    return users


def _drop_meshes(spec: mujoco.MjSpec, meshes: Sequence[mujoco.MjsMesh]) -> None:
    """Delete ``meshes`` and every geom that uses one of them."""
    names = {mesh.name for mesh in meshes}
    users = _users(spec)
    for name in names:
        for geom in users.get(name, ()):
            spec.delete(geom)
    for mesh in list(meshes):
        spec.delete(mesh)


def _resolve_meshes(
    spec: mujoco.MjSpec,
    urdf: bool,
    directory: Path,
    source: str,
    package_paths: tuple[Path, ...],
) -> None:
    """Make every mesh path absolute (URDF; ``package://`` in MJCF); drop undecodable ones."""
    folders: list[Path] | None = None
    users = _users(spec)
    unreadable: list[tuple[mujoco.MjsMesh, Path]] = []
    for mesh in spec.meshes:
        name = mesh.file
        if not name:
            continue  # vertex data given inline
        if not urdf and not name.startswith((*_URI_SCHEMES, "file://")):
            continue  # MuJoCo resolves MJCF paths itself, relative to the file and meshdir
        if folders is None:
            folders = search_folders(package_paths, directory)
        resolved = resolve_mesh_path(
            name, directory, folders, meshdir=spec.meshdir, strip=bool(spec.strippath)
        )
        if resolved is None:
            links = sorted({geom.parent.name for geom in users.get(mesh.name, ())})
            searched = "\n  ".join(str(f) for f in folders) or "(none)"
            raise ModelError(
                f"mesh {name!r} of {source} (links {links}) not found; searched, in order:\n  "
                f"{searched}\npass package_paths=[folder holding the package] to search "
                "elsewhere, or meshes=False to load the kinematics without meshes"
            )
        mesh.file = str(resolved)
        if not _decodable(resolved):
            unreadable.append((mesh, resolved))
    if unreadable:
        listed = ", ".join(
            f"{path.name} ({sorted({g.parent.name for g in users.get(mesh.name, ())})})"
            for mesh, path in unreadable
        )
        warnings.warn(
            f"{source}: dropped {len(unreadable)} mesh(es) in formats MuJoCo cannot read "
            f"(it reads STL, OBJ, MSH): {listed}; convert them to keep their geoms",
            ModelWarning,
            stacklevel=4,
        )
        _drop_meshes(spec, [mesh for mesh, _ in unreadable])
    # Paths are absolute now; a meshdir would be prepended to nothing, strippath would undo them.
    if urdf:
        spec.strippath = False


def _decodable(path: Path) -> bool:
    """Whether MuJoCo has a decoder for the mesh's format (probed once per extension)."""
    extension = path.suffix.lower()
    if extension in _DECODED_MESH_FORMATS:
        return True
    if extension not in _probed_mesh_formats:
        probe = mujoco.MjSpec()
        probe.add_mesh(name="probe", file=str(path))
        probe.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname="probe")
        try:
            probe.compile()
            _probed_mesh_formats[extension] = True
        except ValueError as error:
            _probed_mesh_formats[extension] = "decoder" not in str(error)
    return _probed_mesh_formats[extension]


def _add_floating_base(spec: mujoco.MjSpec, source: str) -> None:
    roots = list(spec.worldbody.bodies)
    if len(roots) != 1:
        raise ModelError(
            f"floating_base=True needs exactly one body under the world in {source}, found "
            f"{[b.name for b in roots]}; add a <freejoint/> to the right body in the MJCF"
        )
    root = roots[0]
    joints = list(root.joints)
    if joints and joints[0].type == mujoco.mjtJoint.mjJNT_FREE:
        return  # floating already
    if joints:
        raise ModelError(
            f"floating_base=True: root body {root.name!r} of {source} already has joints "
            f"{[j.name for j in joints]}"
        )
    if len(spec.keys):
        raise ModelError(
            f"floating_base=True: {source} has keyframes, whose qpos would lose their meaning; "
            "add a <freejoint/> to the root body and its 7 values to each keyframe instead"
        )
    root.add_freejoint(name=FLOATING_BASE_JOINT)


def _first_file(candidates: Iterable[Path]) -> Path | None:
    for candidate in candidates:
        if candidate.is_file():
            return candidate.resolve()
    return None
