"""Loading robot description files (MJCF, URDF) into MuJoCo, ready for kinematics.

MuJoCo reads both formats itself (:meth:`mujoco.MjSpec.from_file`); this module fixes what
stops real-world URDFs from loading or from being useful for inverse kinematics:

* **Mesh paths.** URDFs name meshes ``package://<package>/<path>`` (ROS), ``file://<path>`` or
  relative to the URDF file. Each mesh is resolved to an absolute path by trying, in order,
  the folders in ``package_paths`` and ``ROS_PACKAGE_PATH`` (each with the ROS packages nested
  below it, as in a workspace's ``src``), the ``share`` folders of ``AMENT_PREFIX_PATH``, then
  the model file's own folder and every folder above it (so a package installed as
  ``…/share/<package>/`` is found from any file inside it). For a folder ``F`` the candidates
  of ``package://pkg/rest`` are ``F/pkg/rest`` and, when ``F`` is the package itself (named
  ``pkg``, or its ``package.xml`` says so), ``F/rest``; a relative path ``rest`` is tried
  against the model's folder (and its ``meshdir``) first. A mesh that is found nowhere raises
  :class:`ModelError` naming the folders searched. ``meshes=False`` drops every mesh geom
  instead: a kinematics-only model that needs no mesh file at all (and loads faster).
* **Mesh formats.** MuJoCo decodes STL, OBJ and MSH. Collision meshes in another format
  (COLLADA ``.dae`` is common) are dropped with a :class:`ModelWarning` that lists them.
  MuJoCo's URDF import keeps the collision geometry only (``discardvisual``); ``visual=True``
  keeps the ``<visual>`` geometry too, for rendering, as geoms that never collide.
* **Fixed links.** MuJoCo's URDF import fuses links attached by fixed joints into their parent
  (``<compiler fusestatic="true"/>``), so tool flanges and hands (``tool0``, ``ee_link``,
  ``panda_hand``) vanish. They are kept as jointless bodies here (``fusestatic=False``), so
  every URDF link is a frame, at the URDF link frame.
* **Inertia.** Kinematic URDFs often omit inertias, and CAD exports break the triangle
  inequality of principal moments or even give indefinite tensors; mass and inertia are
  bounded from below (``boundmass``/``boundinertia``), URDF inertias balanced
  (``balanceinertia``) and indefinite ones replaced by the nearest positive-definite tensor
  (with a :class:`ModelWarning`). None of this changes a valid link, nor any kinematics.
* **Floating base.** MuJoCo's URDF import fixes the root link to the world. With
  ``floating_base=True`` a free joint named ``floating_base`` is added to the root body (its
  ``qpos`` is ``(x, y, z, qw, qx, qy, qz)``, starting at the root's pose in the file), as
  legged robots and humanoids need; the same works on an MJCF with one top-level body, whose
  keyframes then start with the root's pose (and zero velocity).

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
import itertools
import os
import xml.etree.ElementTree as ElementTree
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path

import mujoco
import numpy as np

from redik.core.exceptions import InvalidInput, ModelError, ModelWarning, UnknownFrame, warn
from redik.core.validate import flag
from redik.core.validate import path as checked_path

# Mesh formats MuJoCo decodes without a plugin; other extensions are probed once per run.
_DECODED_MESH_FORMATS = {".stl", ".obj", ".msh"}
_probed_mesh_formats: dict[str, bool] = {}

_URI_SCHEMES = ("package://", "model://")

FLOATING_BASE_JOINT = "floating_base"

#: How deep below a package path :func:`search_folders` looks for ROS packages.
PACKAGE_DEPTH = 3


@dataclasses.dataclass(frozen=True)
class _Options:
    """How a model file is loaded; every field is an argument of :func:`load_spec`."""

    meshes: bool = True
    visual: bool = False
    package_paths: tuple[Path, ...] = ()
    floating_base: bool = False
    keep_fixed_links: bool = True


def load_spec(
    source: str | Path,
    *,
    meshes: bool = True,
    visual: bool = False,
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
        visual: Keep the URDF's ``<visual>`` geometry too (for rendering), as geoms of group 1
            that never collide (``contype = conaffinity = 0``). MuJoCo's URDF import discards it
            by default; collision geometry is kept either way.
        package_paths: Folders searched first for ``package://`` and relative mesh paths:
            folders that contain ROS packages, or a package folder itself.
        floating_base: Add a free joint to the root body (URDF, or MJCF with one top-level
            body, whose keyframes gain the root's initial pose).
        keep_fixed_links: Keep links attached by fixed joints as bodies (URDF only).

    Raises:
        ModelError: the file is missing, unreadable, a mesh cannot be found, or
            ``floating_base`` cannot be applied.
    """
    options = _options(meshes, visual, package_paths, floating_base, keep_fixed_links)
    path = checked_path(source, "source")
    if not path.is_file():
        raise ModelError(f"robot file not found: {str(path)!r}")
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as error:
        raise ModelError(f"cannot read {str(path)!r}: {error}") from None
    urdf = path.suffix.lower() == ".urdf" or _root_tag(text) == "robot"
    return _load(text, urdf, path.resolve().parent, str(path), options, from_file=True)


def load_spec_from_string(
    xml: str,
    *,
    directory: str | Path | None = None,
    meshes: bool = True,
    visual: bool = False,
    package_paths: Sequence[str | Path] | str | Path | None = None,
    floating_base: bool = False,
    keep_fixed_links: bool = True,
) -> mujoco.MjSpec:
    """:func:`load_spec` for an MJCF or URDF string; relative paths start at ``directory``.

    ``directory`` defaults to the current working directory.
    """
    options = _options(meshes, visual, package_paths, floating_base, keep_fixed_links)
    if not isinstance(xml, str):
        raise InvalidInput(f"the model must be an XML string, got {type(xml).__name__}")
    base = checked_path(directory, "directory").resolve() if directory is not None else Path.cwd()
    urdf = _root_tag(xml) == "robot"
    return _load(xml, urdf, base, "the model string", options, from_file=False)


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
        hint = "; load with meshes=False to skip the meshes" if spec.meshes else ""
        raise ModelError(f"MuJoCo could not compile {source}: {error}{hint}") from None


def search_folders(
    package_paths: Sequence[str | Path] | str | Path | None = None,
    model_directory: str | Path | None = None,
) -> list[Path]:
    """The folders searched for meshes, in order (see the module notes); existing ones only.

    Each folder of ``package_paths`` and ``ROS_PACKAGE_PATH`` is followed by the ROS packages
    (folders holding a ``package.xml``) up to :data:`PACKAGE_DEPTH` levels below it, as
    ``rospack`` finds the packages of a workspace's ``src``.
    """
    explicit = [p.expanduser() for p in _as_paths(package_paths)]
    explicit += [Path(p) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
    folders: list[Path] = []
    for folder in explicit:
        folders += [folder, *_packages_below(folder, PACKAGE_DEPTH)]
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


def _packages_below(folder: Path, depth: int) -> list[Path]:
    """Folders holding a ``package.xml`` within ``depth`` levels below ``folder`` (not hidden)."""
    found: list[Path] = []
    if depth <= 0:
        return found
    try:
        entries = sorted(os.scandir(folder), key=lambda entry: entry.name)
    except OSError:
        return found
    for entry in entries:
        if entry.name.startswith(".") or not entry.is_dir(follow_symlinks=False):
            continue
        child = Path(entry.path)
        if (child / "package.xml").is_file():
            found.append(child)  # a package holds no other package
        else:
            found += _packages_below(child, depth - 1)
    return found


def _package_name(folder: Path) -> str | None:
    """The ``<name>`` in ``folder/package.xml`` (a ROS package), else None."""
    manifest = folder / "package.xml"
    if not manifest.is_file():
        return None
    try:
        name = ElementTree.parse(manifest).getroot().findtext("name")
    except (ElementTree.ParseError, OSError):
        return None
    return name.strip() if name else None


def resolve_mesh_path(
    name: str,
    model_directory: str | Path,
    folders: Iterable[Path],
    *,
    meshdir: str = "",
) -> Path | None:
    """The file a URDF/MJCF mesh reference names, or None when no candidate exists.

    ``name`` is ``package://pkg/rest``, ``model://pkg/rest``, ``file://path``, an absolute
    path or a path relative to ``model_directory`` (tried inside ``meshdir`` first; with
    ``strippath`` MuJoCo has already cut it to the file name while parsing).
    """
    model_directory = Path(model_directory)
    for scheme in _URI_SCHEMES:
        if name.startswith(scheme):
            package, _, rest = name[len(scheme) :].partition("/")
            return _first_file(_package_candidates(package, rest, folders))
    if name.startswith("file://"):
        name = name[len("file://") :]
    relative = Path(name)
    if relative.is_absolute():
        return relative if relative.is_file() else None
    local = [model_directory / meshdir / relative] if meshdir else []
    local.append(model_directory / relative)
    return _first_file(itertools.chain(local, (folder / relative for folder in folders)))


def _package_candidates(package: str, rest: str, folders: Iterable[Path]) -> Iterator[Path]:
    """``F/package/rest`` for each folder ``F``, and ``F/rest`` when ``F`` is the package.

    A generator, so that the search stops at the first file found: a model's meshes usually
    sit in the first folders, and building every candidate (reading each folder's
    ``package.xml``) for every mesh took half of :func:`load_spec` on talos (37 meshes).
    """
    for folder in folders:
        yield folder / package / rest
        if folder.name == package or _package_name(folder) == package:
            yield folder / rest


_FRAME_OBJECTS = {
    "site": mujoco.mjtObj.mjOBJ_SITE,
    "body": mujoco.mjtObj.mjOBJ_BODY,
    "geom": mujoco.mjtObj.mjOBJ_GEOM,
}
_LISTED_NAMES = 100  # per kind, so that a message about a 1000-geom scene stays readable


def unknown_frame(
    model: mujoco.MjModel,
    name: str,
    label: str = "the model",
    kinds: Sequence[str] = ("site", "body", "geom"),
) -> UnknownFrame:
    """The :class:`UnknownFrame` for a frame name that names no object of ``kinds`` in ``model``.

    The message gives the closest names (:func:`difflib.get_close_matches`, then names that
    contain ``name``; a ``"kind:"`` prefix is ignored) and lists the names of every kind. A
    geom of that name is pointed out when geoms are not among ``kinds``.
    """
    names = {kind: object_names(model, _FRAME_OBJECTS[kind]) for kind in kinds}
    everything = [n for kind in kinds for n in names[kind]]
    prefix, _, rest = str(name).partition(":")
    bare = rest if rest and prefix in _FRAME_OBJECTS else str(name)
    lowered = bare.lower()
    containing = [n for n in everything if lowered and lowered in n.lower()]
    close = difflib.get_close_matches(bare, everything, n=5, cutoff=0.5)
    close = list(dict.fromkeys(close + containing))[:5]
    parts = [f"no {' or '.join(kinds)} named {name!r} in {label}"]
    if close:
        parts.append(f"did you mean {', '.join(map(repr, close))}?")
    if "geom" not in kinds and mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, bare) >= 0:
        parts.append(f"{bare!r} is a geom, which is not a frame here: add a site, or use its body")
    for kind in kinds:
        listed = names[kind][:_LISTED_NAMES]
        more = len(names[kind]) - len(listed)
        plural = "bodies" if kind == "body" else f"{kind}s"
        parts.append(f"{plural}: {listed}" + (f" and {more} more" if more > 0 else ""))
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


def _options(
    meshes: bool,
    visual: bool,
    package_paths: Sequence[str | Path] | str | Path | None,
    floating_base: bool,
    keep_fixed_links: bool,
) -> _Options:
    return _Options(
        meshes=flag(meshes, "meshes"),
        visual=flag(visual, "visual"),
        package_paths=tuple(p.expanduser() for p in _as_paths(package_paths)),
        floating_base=flag(floating_base, "floating_base"),
        keep_fixed_links=flag(keep_fixed_links, "keep_fixed_links"),
    )


def _as_paths(paths: Sequence[str | Path] | str | Path | None) -> list[Path]:
    """``package_paths`` as a list of paths: None, one path, or a sequence of paths."""
    if paths is None:
        return []
    if isinstance(paths, (str, os.PathLike)):
        return [checked_path(paths, "package_paths")]
    if not isinstance(paths, Iterable):
        raise InvalidInput(f"package_paths must be a path or a list of paths, got {paths!r}")
    return [checked_path(p, f"package_paths[{i}]") for i, p in enumerate(paths)]


def _load(
    text: str, urdf: bool, directory: Path, source: str, options: _Options, *, from_file: bool
) -> mujoco.MjSpec:
    """Parse the model (a URDF edited first, :func:`_edit_urdf`) and :func:`_prepare` it.

    An unedited file is read by MuJoCo from its path, so that its includes and assets resolve
    as MuJoCo resolves them; text is parsed from the string, with ``directory`` as the model
    file's folder, so relative paths name the same files as for a file there.
    """
    edited = _edit_urdf(text, options) if urdf else None
    if from_file and edited is None:
        spec = _parse(None, text, source)
    else:
        spec = _parse(text if edited is None else edited, text, source)
        spec.modelfiledir = str(directory) + os.sep
    _prepare(spec, urdf, directory, source, options)
    return spec


def _parse(xml: str | None, text: str, source: str) -> mujoco.MjSpec:
    """``MjSpec.from_string(xml)``, or ``from_file(source)`` when ``xml`` is None."""
    try:
        if xml is None:
            return mujoco.MjSpec.from_file(source)
        return mujoco.MjSpec.from_string(xml)
    except ValueError as error:
        hint = ""
        if _root_tag(text) == "sdf":
            hint = "; MuJoCo reads MJCF and URDF, not SDF: convert the file to URDF first"
        elif source.endswith(".xacro") or "xacro" in text or "$(" in text:
            hint = (
                "; this looks like a xacro file: expand it first (xacro robot.xacro > robot.urdf)"
            )
        raise ModelError(f"MuJoCo could not load {source}: {error}{hint}") from None


def _edit_urdf(urdf: str, options: _Options) -> str | None:
    """The URDF text as MuJoCo should read it, or None when it needs no change.

    ``visual`` adds ``<mujoco><compiler discardvisual="false"/></mujoco>`` (MuJoCo's URDF
    extension); ``meshes=False`` removes the ``<visual>``/``<collision>`` elements of mesh
    geometry before MuJoCo parses them (far faster than deleting their geoms from the spec).
    """
    if options.meshes and not options.visual:
        return None
    try:
        root = ElementTree.fromstring(urdf)
    except ElementTree.ParseError:
        return None  # MuJoCo's parser reports the error, with the file's name
    if options.visual:
        extension = root.find("mujoco")
        if extension is None:
            extension = ElementTree.SubElement(root, "mujoco")
        compiler = extension.find("compiler")
        if compiler is None:
            compiler = ElementTree.SubElement(extension, "compiler")
        compiler.set("discardvisual", "false")
    if not options.meshes:
        for link in root.iter("link"):
            for element in list(link):
                if element.tag in ("visual", "collision") and (
                    element.find("geometry/mesh") is not None
                ):
                    link.remove(element)
    return ElementTree.tostring(root, encoding="unicode")


def _root_tag(text: str) -> str | None:
    """The tag of the document's root element (``robot`` for URDF, ``mujoco`` for MJCF)."""
    try:
        for _, element in ElementTree.iterparse(io.StringIO(text), events=("start",)):
            return element.tag
    except ElementTree.ParseError:
        return None  # MuJoCo's own parser reports the error with a line number
    return None


def _prepare(
    spec: mujoco.MjSpec, urdf: bool, directory: Path, source: str, options: _Options
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
    """Make singular or indefinite URDF inertia tensors positive definite (MuJoCo rejects them).

    The symmetric tensor ``I = V diag(λ) Vᵀ`` becomes ``V diag(max(λ, ε)) Vᵀ`` with
    ``ε = max(10⁻¹², 10⁻³ max λ)``: the nearest positive-definite tensor with the same principal
    axes. Zero tensors (massless helper links) are bounded silently, like ``boundinertia``;
    indefinite ones (negative moments, CAD-export errors) with a :class:`ModelWarning`.
    Kinematics never reads inertia.
    """
    indefinite = []
    for body in spec.bodies:
        full = np.asarray(body.fullinertia, dtype=float)
        if not np.all(np.isfinite(full)):
            continue  # diagonal inertia given (or none): boundinertia and balanceinertia apply
        xx, yy, zz, xy, xz, yz = full.tolist()
        tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        if xx > 0.0 and xx * yy - xy * xy > 0.0 and np.linalg.det(tensor) > 0.0:
            continue  # positive definite (Sylvester's criterion)
        eigenvalues, axes = np.linalg.eigh(tensor)
        if eigenvalues[0] > 0.0:
            continue
        if eigenvalues[0] < -1e-12 * max(1.0, abs(float(eigenvalues[-1]))):
            indefinite.append(body.name)
        floor = max(1e-12, 1e-3 * float(eigenvalues[-1]))
        tensor = axes @ np.diag(np.maximum(eigenvalues, floor)) @ axes.T
        body.fullinertia = [*np.diag(tensor), tensor[0, 1], tensor[0, 2], tensor[1, 2]]
    if indefinite:
        warn(
            f"{source}: the inertia tensors of links {indefinite} are indefinite; replaced by "
            "the nearest positive-definite tensor with the same principal axes",
            ModelWarning,
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
        resolved = resolve_mesh_path(name, directory, folders, meshdir=spec.meshdir)
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
        warn(
            f"{source}: dropped {len(unreadable)} mesh(es) in formats MuJoCo cannot read "
            f"(it reads STL, OBJ, MSH): {listed}; convert them to keep their geoms",
            ModelWarning,
        )
        _drop_meshes(spec, [mesh for mesh, _ in unreadable])
    if folders is not None:  # some paths are absolute now: strippath would undo them
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
    initial = None
    if any(len(key.qpos) or len(key.qvel) for key in spec.keys):
        # Keyframes grow by the free joint's values (first in qpos: the root is the only top
        # body): its initial pose, read off a mesh-free, key-free copy, and zero velocity.
        probe = spec.copy()
        for key in list(probe.keys):
            probe.delete(key)
        _drop_meshes(probe, probe.meshes)
        probe.worldbody.first_body().add_freejoint()
        initial = compile_spec(probe, source).qpos0[:7].tolist()
    root.add_freejoint(name=FLOATING_BASE_JOINT)
    if initial is not None:
        for key in spec.keys:
            if len(key.qpos):
                key.qpos = [*initial, *key.qpos]
            if len(key.qvel):
                key.qvel = [0.0] * 6 + list(key.qvel)


def _first_file(candidates: Iterable[Path]) -> Path | None:
    """The first existing file, absolute and without ``..`` (symlinks kept: no realpath)."""
    for candidate in candidates:
        if candidate.is_file():
            return Path(os.path.abspath(candidate))
    return None
