"""Configuration launch files (the thesis's Listing 6.1).  Pure: no LSP here.

A configuration launch file sets every feature arg of a generic launch file to ``true`` or
``false`` and includes the generic file through ``$(find pkg)``, passing each arg on::

    <launch>
      <arg name="Turtlerand" value="true"/>
      ...
      <include file="$(find turtlerand)/launch/generic.launch">
        <arg name="Turtlerand" value="$(arg Turtlerand)"/>
        ...
      </include>
    </launch>

Names are deterministic (derived from the selected features) and files are only ever
planned inside one of the given workspace roots.
"""

from __future__ import annotations

import hashlib
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Mapping, Optional, Sequence

from xml.sax.saxutils import escape

from ..base.files import read_text_or_none
from ..base.safewrite import WriteError, check_paths, write_paths


def quoteattr(value: str) -> str:
    """A double-quoted XML attribute value."""
    return '"' + escape(value, {'"': "&quot;"}) + '"'


@dataclass(frozen=True)
class GeneratedFile:
    path: str
    text: str
    product: dict[str, bool] = field(default_factory=dict, compare=False)


class GenerateError(ValueError):
    """A request that cannot be satisfied (e.g. a folder outside the workspace)."""


# ------------------------------------------------------------------ packages

_NAME_RE = re.compile(r"<name>\s*([^<\s]+)\s*</name>")


def find_package(path: str, read_file=None, stop_at: Sequence[str] = ()) -> tuple[Optional[str], Optional[str]]:
    """The catkin package containing ``path``: (package name, package folder) or (None, None).

    Looks for the nearest ``package.xml`` upwards and reads its ``<name>`` (no XML parser:
    the file is never trusted with entities)."""
    p = Path(path).absolute()
    stops = {str(Path(s).absolute()) for s in stop_at}
    for d in [p.parent, *p.parent.parents]:
        manifest = d / "package.xml"
        text = None
        try:
            if read_file is not None:
                text = read_file(str(manifest))
            else:
                text = read_text_or_none(str(manifest))  # regular files within the size cap only
        except OSError:
            text = None
        if text:
            m = _NAME_RE.search(text)
            if m:
                return m.group(1), str(d)
        if str(d) in stops:
            break
    return None, None


# ------------------------------------------------------------------ products

def normalise_product(product, features: Sequence[str]) -> dict[str, bool]:
    """A product as the analyses give it (a mapping name -> bool, or the set of selected
    names; names long "Root.A" or short "A") -> {feature arg: bool} for ``features``."""
    if isinstance(product, Mapping):
        selected = {str(k) for k, v in product.items() if v}
    else:
        selected = {str(x) for x in product}
    short = {s.rsplit(".", 1)[-1] for s in selected}
    return {f: (f in selected or f in short) for f in features}


def configuration_name(product: Mapping[str, bool], features: Sequence[str], prefix: str = "config",
                       omit: Iterable[str] = (), suffix: str = ".launch") -> str:
    """Deterministic file name for a product: the selected features, in ``features`` order
    (leaving out ``omit``, e.g. the root, which every product selects)."""
    skip = set(omit)
    on = [f for f in features if product.get(f) and f not in skip]
    body = "-".join(re.sub(r"[^A-Za-z0-9_]+", "_", f).lower() for f in on) or "none"
    if len(body) > 80:
        digest = hashlib.sha1("|".join(on).encode()).hexdigest()[:10]
        body = f"{body[:60]}-{digest}"
    return f"{prefix}_{body}{suffix}"


def include_target(generic_path: str, package: Optional[str], package_dir: Optional[str],
                   out_dir: Optional[str] = None, dialect: str = "ros1") -> str:
    """How the configuration file names the generic file: ``$(find pkg)/rel`` (ROS 2:
    ``$(find-pkg-share pkg)/rel``) when the generic file is in a package, else
    ``$(dirname)/rel`` relative to ``out_dir``."""
    gp = Path(generic_path).absolute()
    if package and package_dir:
        try:
            rel = gp.relative_to(Path(package_dir).absolute())
            find = "find-pkg-share" if dialect == "ros2" else "find"
            return f"$({find} {package})/{rel.as_posix()}"
        except ValueError:
            pass
    if out_dir:
        rel = os.path.relpath(gp, Path(out_dir).absolute())
        return f"$(dirname)/{Path(rel).as_posix()}"
    return gp.as_posix()


def render_configuration(product: Mapping[str, bool], features: Sequence[str], include_file: str,
                         indent: str = "  ") -> str:
    """The text of one configuration launch file (Listing 6.1)."""
    lines = ["<launch>"]
    for f in features:
        lines.append(f'{indent}<arg name={quoteattr(f)} value="{"true" if product.get(f) else "false"}"/>')
    lines.append(f"{indent}<include file={quoteattr(include_file)}>")
    for f in features:
        lines.append(f'{indent * 2}<arg name={quoteattr(f)} value={quoteattr(f"$(arg {f})")}/>')
    lines.append(f"{indent}</include>")
    lines.append("</launch>")
    return "\n".join(lines) + "\n"


def render_configuration_ros2(product: Mapping[str, bool], features: Sequence[str], include_file: str,
                              indent: str = "  ", choice_values: Optional[Mapping[str, str]] = None) -> str:
    """A ROS 2 configuration launch file: the generic file included with each feature arg set
    (ros2 launch passes an include's args on; no top-level args are needed), and each
    ``<choice>`` arg set to the selected alternative."""
    lines = ["<launch>", f"{indent}<include file={quoteattr(include_file)}>"]
    for f in features:
        lines.append(f'{indent * 2}<arg name={quoteattr(f)} value="{"true" if product.get(f) else "false"}"/>')
    for name, value in (choice_values or {}).items():
        lines.append(f"{indent * 2}<arg name={quoteattr(name)} value={quoteattr(value)}/>")
    lines.append(f"{indent}</include>")
    lines.append("</launch>")
    return "\n".join(lines) + "\n"


def ros2_choices(analysis, model) -> dict[str, dict[str, str]]:
    """The ``<choice>`` args of a ROS 2 generic file that pair with an alternative group of the
    model: arg -> {value: the feature that selects it} (tvl_lsp.analysis.choices)."""
    if getattr(analysis, "dialect", "ros1") != "ros2" or not getattr(analysis, "choices", None) or model is None:
        return {}
    from ..analysis.choices import pair_choices
    from ..analysis.encode import encode
    enc = encode(model)
    pairs = pair_choices({k: v[0] for k, v in analysis.choices.items()}, enc)
    return {k: {v: f for v, f in p.by_value.items() if v in analysis.choices[k][0]}
            for k, p in pairs.items() if p.kind == "group"}


def choice_values(product: Mapping[str, bool], choices: Mapping[str, Mapping[str, str]]) -> dict[str, str]:
    """The value of each paired ``<choice>`` arg in a product (the selected alternative)."""
    selected = {str(k) for k, v in product.items() if v}
    short = {x.rsplit(".", 1)[-1] for x in selected}
    out = {}
    for name, by_value in choices.items():
        for value, feature in by_value.items():
            if feature in selected or feature in short:
                out[name] = value
                break
    return out


def render_configuration_python(product: Mapping[str, bool], features: Sequence[str], include_file: str,
                                indent: str = "    ", choice_values: Optional[Mapping[str, str]] = None,
                                source: str = "") -> str:
    """A ROS 2 Python configuration launch file: the generic file (Python, XML or YAML: ros2/launch's
    ``AnyLaunchDescriptionSource``) included with each feature arg set and each ``<choice>`` arg
    set to the selected alternative.  ``include_file`` is a Python expression (see
    :func:`python_include_target`)."""
    args = [(f, "true" if product.get(f) else "false") for f in features]
    args += list((choice_values or {}).items())
    lines = [f'"""One product of {source or "the model"}: written by tvl-lsp generate."""', "",
             "from launch import LaunchDescription",
             "from launch.actions import IncludeLaunchDescription",
             "from launch.launch_description_sources import AnyLaunchDescriptionSource"]
    if "FindPackageShare" in include_file:
        lines.append("from launch.substitutions import PathJoinSubstitution")
        lines.append("from launch_ros.substitutions import FindPackageShare")
    elif "ThisLaunchFileDir" in include_file:
        lines.append("from launch.substitutions import PathJoinSubstitution, ThisLaunchFileDir")
    lines += ["", "", "def generate_launch_description():", f"{indent}return LaunchDescription([",
              f"{indent * 2}IncludeLaunchDescription(", f"{indent * 3}AnyLaunchDescriptionSource({include_file}),",
              f"{indent * 3}launch_arguments=["]
    for name, value in args:
        lines.append(f"{indent * 4}({name!r}, {value!r}),")
    lines += [f"{indent * 3}],", f"{indent * 2}),", f"{indent}])"]
    return "\n".join(lines) + "\n"


def python_include_target(generic_path: str, package: Optional[str], package_dir: Optional[str],
                          out_dir: Optional[str] = None) -> str:
    """How a Python configuration file names the generic file: the package's share folder
    (``FindPackageShare``) when it is in a package, else the path relative to the configuration
    file (``ThisLaunchFileDir``)."""
    gp = Path(generic_path).absolute()
    if package and package_dir:
        try:
            rel = gp.relative_to(Path(package_dir).absolute())
            return f"PathJoinSubstitution([FindPackageShare({package!r}), {rel.as_posix()!r}])"
        except ValueError:
            pass
    if out_dir:
        rel = os.path.relpath(gp, Path(out_dir).absolute())
        return f"PathJoinSubstitution([ThisLaunchFileDir(), {Path(rel).as_posix()!r}])"
    return repr(gp.as_posix())


# ------------------------------------------------------------------ launch formats

@dataclass(frozen=True)
class ConfigWriter:
    """How configuration files of one launch format are written: the generate hook.  A launch
    dialect registers its writer (:func:`register_writer`); :func:`plan_configurations` asks
    :func:`writer_for` which one a generic file gets.

    ``include(generic_path, package, package_dir, out_dir)``: how a configuration names the
    generic file; ``render(product, features, include, indent, choice_values, source)``: the
    text of one configuration (``features``: the feature args, ``choice_values``: ROS 2
    ``<choice>`` args and their values, ``source``: the generic file's name)."""
    name: str
    suffix: str
    include: Callable[..., str]
    render: Callable[..., str]
    ros2: bool = True       # ros2/launch semantics: <choice> args, args passed on by includes
    indent: str = "  "


def _xml1(product, features, include, indent, choice_values, source):
    return render_configuration(product, features, include, indent)


def _xml2(product, features, include, indent, choice_values, source):
    return render_configuration_ros2(product, features, include, indent, choice_values)


def _py(product, features, include, indent, choice_values, source):
    return render_configuration_python(product, features, include, indent, choice_values, source)


WRITERS: dict[str, ConfigWriter] = {}


def register_writer(w: ConfigWriter) -> None:
    WRITERS[w.name] = w


register_writer(ConfigWriter("ros1", ".launch", lambda g, p, d, o: include_target(g, p, d, o, "ros1"), _xml1,
                             ros2=False))
register_writer(ConfigWriter("ros2", ".launch.xml", lambda g, p, d, o: include_target(g, p, d, o, "ros2"), _xml2))
register_writer(ConfigWriter("python", ".launch.py", python_include_target, _py, indent="    "))

PYTHON_SUFFIXES = (".launch.py", "_launch.py")


def writer_for(dialect: str = "ros1", generic_path: str = "", fmt: Optional[str] = None) -> ConfigWriter:
    """The writer for configurations of ``generic_path`` (read as ``dialect``): ``fmt`` when
    given ("xml": the dialect's XML, "python", or any registered name), else the dialect's XML --
    for a Python generic file too: an XML launch file that includes the ``.launch.py`` with the
    product's arguments (issue #25; ros2 launch's XML front end includes Python files)."""
    if fmt in (None, "", "auto"):
        fmt = "xml"
    if fmt == "xml":
        fmt = "ros2" if dialect == "ros2" else "ros1"
    w = WRITERS.get(fmt)
    if w is None:
        raise GenerateError(f"no configuration format {fmt!r} (known: xml, {', '.join(sorted(WRITERS))})")
    if w.ros2 and dialect != "ros2" and fmt == "python":
        raise GenerateError("Python configuration files are ROS 2 launch files: the generic file is read as "
                            "ROS 1 (roslaunch) XML")
    return w


def inside(path: str, roots: Iterable[str]) -> bool:
    """Is ``path`` (after resolving ``..`` and symlinks) inside one of ``roots``?"""
    try:
        p = Path(os.path.realpath(path))
    except (OSError, ValueError):
        return False
    for r in roots:
        try:
            p.relative_to(Path(os.path.realpath(r)))
            return True
        except ValueError:
            continue
    return False


def resolve_folder(folder: Optional[str], generic_path: str, roots: Sequence[str]) -> str:
    """The output folder: ``folder`` (absolute, or relative to the generic file's package
    folder — else to the first workspace root), default ``configs`` beside the generic
    file's ``launch`` folder.  Raises GenerateError when it is outside every root."""
    _, pkg_dir = find_package(generic_path, stop_at=roots)
    base = Path(pkg_dir) if pkg_dir else (Path(roots[0]) if roots else Path(generic_path).parent)
    if not folder:
        out = base / "configs"
    elif os.path.isabs(folder):
        out = Path(folder)
    else:
        out = base / folder
    out = Path(os.path.normpath(str(out.absolute())))
    if roots and not inside(str(out), roots):
        raise GenerateError(f"the folder {out} is outside the workspace; choose a folder inside it")
    return str(out)


def plan_configurations(products: Iterable, features: Sequence[str], generic_path: str, out_dir: str,
                        roots: Sequence[str] = (), package: Optional[str] = None,
                        package_dir: Optional[str] = None, prefix: Optional[str] = None,
                        indent: Optional[str] = None, limit: Optional[int] = None,
                        omit: Iterable[str] = (), dialect: str = "ros1",
                        choices: Optional[Mapping[str, Mapping[str, str]]] = None,
                        writer: Optional[ConfigWriter] = None,
                        names: Optional[Sequence[str]] = None) -> list[GeneratedFile]:
    """One :class:`GeneratedFile` per product (at most ``limit``), sorted by path.  ``dialect``
    "ros2": ROS 2 files (``.launch.xml``, ``$(find-pkg-share)``, args passed to the include;
    ``choices``: see :func:`ros2_choices`); ``writer``: the launch format to write (default
    :func:`writer_for` the dialect and the generic file).  ``names``: the file name of each
    product (a plain name, no folder), instead of one made from its selected features."""
    if package is None and package_dir is None:
        package, package_dir = find_package(generic_path, stop_at=roots)
    w = writer or writer_for(dialect, generic_path)
    indent = w.indent if indent is None else indent
    target = w.include(generic_path, package, package_dir, out_dir)
    covered = {f for by in (choices or {}).values() for f in by.values()}
    if w.ros2:
        features = [f for f in features if f not in (choices or {}) and f not in covered]
    prefix = prefix or Path(generic_path).name.split(".")[0]
    source = Path(generic_path).name
    files: dict[str, GeneratedFile] = {}
    seen: dict[str, GeneratedFile] = {}
    for i, prod in enumerate(products):
        if limit is not None and i >= limit:
            break
        p = normalise_product(prod, features)
        if w.ros2:
            cv = choice_values(prod if isinstance(prod, Mapping) else {x: True for x in prod}, choices or {})
            named = dict(p)
            named.update({v: True for v in cv.values()})
            name = configuration_name(named, list(features) + list(cv.values()), prefix, omit, w.suffix)
        else:
            cv = {}
            name = configuration_name(p, features, prefix, omit, w.suffix)
        path = str(Path(out_dir) / (names[i] if names is not None else name))
        text = w.render(p, features, target, indent, cv, source)
        if roots and not inside(path, roots):
            raise GenerateError(f"{path} would be outside the workspace")
        # one file per product: two products with one name would overwrite each other (names
        # are lower case: on a case-insensitive file system so would names differing in case)
        key = os.path.normcase(path).casefold()
        other = seen.get(key)
        if other is not None and other.product != p:
            raise GenerateError(_collision_message(path, other.product, p, features))
        seen[key] = files[path] = GeneratedFile(path, text, p)
    return [files[k] for k in sorted(files)]


def write_configurations(files: Iterable, roots: Sequence[str]) -> list[str]:
    """Write planned configuration files (:class:`GeneratedFile` or ``{"path", "text"}``
    dicts) inside ``roots``: the one writer of the three hosts (``tvl-lsp generate``, the
    editor command, the configurator's Generate).  Atomic, never through a symbolic link, the
    output folder opened once from the root (:mod:`tvl_lsp.base.safewrite`); every target is
    checked before the first is written.  Returns the paths written; raises
    :class:`~tvl_lsp.base.safewrite.WriteError` (an ``OSError`` whose text is one line)."""
    texts: dict[str, str] = {}
    for f in files:
        path, text = (f["path"], f["text"]) if isinstance(f, Mapping) else (f.path, f.text)
        texts[path] = text
    if not roots:
        raise WriteError(next(iter(texts), "?"), "no workspace folder to write in")
    try:
        return write_paths(texts, within=list(roots))
    except WriteError as exc:
        exc.total = len(texts)  # (for safewrite.summary)
        raise


def check_configurations(files: Iterable, roots: Sequence[str]) -> None:
    """Raise WriteError when a planned file could not be written safely (a link, a FIFO, a
    folder that is a link, outside ``roots``): for a host that lets the editor write them."""
    check_paths([f["path"] if isinstance(f, Mapping) else f.path for f in files], within=list(roots))


def _collision_message(path: str, a: Mapping[str, bool], b: Mapping[str, bool], features: Sequence[str]) -> str:
    """Why two products get the same file name: the feature names that differ only in case
    or punctuation, when that is the reason."""
    by_token: dict[str, list[str]] = {}
    for f in features:
        by_token.setdefault(re.sub(r"[^A-Za-z0-9_]+", "_", f).casefold(), []).append(f)
    clashes = [names for names in by_token.values() if len(names) > 1]
    name = Path(path).name
    if clashes:
        which = "; ".join(" and ".join(f"`{n}`" for n in names) for names in clashes)
        return (f"feature names {which} differ only in case or punctuation, so two configurations "
                f"would both be written to {name}: rename one of them (nothing was written)")
    return (f"two configurations would both be written to {name} (a name shortened by its digest): "
            "nothing was written")
