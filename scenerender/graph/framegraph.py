"""The frame graph: passes, versioned resource handles, culling, caching, dumps.

Two kinds of resource live in the graph:

- *Inputs* are imported: what the world hands the frame (the camera, each light, the
  object transforms...). Each is static or dynamic over the animation, decided by whoever
  imports it, and no pass writes it.
- *Images* (colour and depth targets) are created by the pass that first writes them.
  Writing one again makes a new *version* of its handle, so "the skybox draws over the
  opaque colour" is an explicit edge: the skybox reads version 1 and writes version 2.

Each pass has a ``setup(builder)`` that declares everything it reads and writes and
returns a frozen data object (the handles it created), and an ``execute(ctx, data)`` that
does the work. The backend hands ``execute`` only what ``setup`` declared; anything else
is an error (:class:`UndeclaredResource`).

Compiling walks back from the passes with side effects (the readback) and drops every pass
nothing needs. A pass is *static* when everything it reads is: a static input, or an image
made by a static pass; and no dynamic pass draws over the image it made. It then executes
once and its results stay in place for all later frames. Nothing else decides it: a pass
that reads an animated input is dynamic.
"""
from __future__ import annotations

from dataclasses import dataclass, field

# Image formats the GL backend allocates (gpu.resources.allocate makes each of these).
COLOR_FORMATS = ("rgba8", "srgba8", "rgba16f", "rgba32f", "r8", "r16ui", "r32f", "r32ui", "rgba32ui")
# "camera_depth" is the depth format the device's depth convention picks (gpu.depth).
DEPTH_FORMATS = ("depth24", "camera_depth")


class UndeclaredResource(LookupError):
    """A pass used a resource its ``setup`` did not declare (a bug in the pass)."""


@dataclass(frozen=True)
class ResourceDesc:
    """An image the backend allocates once per run.

    kind:    "color" (format in COLOR_FORMATS) or "depth" (format in DEPTH_FORMATS).
    size:    (width, height) in texels.
    samples: MSAA sample count; 0 or 1 means single-sampled (a texture), more means a
             multisampled target that must be resolved before it is sampled as a texture.
    """

    kind: str
    size: tuple
    format: str
    samples: int = 0

    def __post_init__(self):
        formats = {"color": COLOR_FORMATS, "depth": DEPTH_FORMATS}.get(self.kind)
        if formats is None or self.format not in formats:
            raise ValueError(f"no {self.kind} image of format {self.format!r}; "
                             f"colour formats: {', '.join(COLOR_FORMATS)}; depth formats: {', '.join(DEPTH_FORMATS)}")

    def describe(self) -> str:
        text = f"{self.kind} {self.format} {self.size[0]}x{self.size[1]}"
        return text + (f" x{self.samples} MSAA" if self.samples > 1 else "")


@dataclass(frozen=True)
class InputDesc:
    """A per-frame value the world imports into the graph.

    dynamic: True when the value can change over the animation.
    what:    one line for graph dumps (e.g. "animated: position, target").
    """

    dynamic: bool
    what: str = ""

    def describe(self) -> str:
        return ("dynamic" if self.dynamic else "static ") + (f"  {self.what}" if self.what else "")


@dataclass(frozen=True)
class Handle:
    """A versioned reference to a graph resource; passes only ever hold handles.
    Inputs have version 0 (no pass writes them); images start at 1."""

    resource: int
    version: int
    name: str

    def __str__(self) -> str:
        return self.name if self.version == 0 else f"{self.name}#{self.version}"


class RenderPass:
    """Base class of every pass. Subclasses set ``name`` and implement setup/execute.

    Passes are configuration only (frozen dataclasses in practice): ``setup`` declares and
    returns its data, it does not store anything on the pass.
    ``side_effect``: True for passes whose work leaves the graph (readback to a sink).
    ``keeps_unchanged``: True for passes whose result is a function of what they read
    alone: a dynamic pass like that keeps its last result in a frame where nothing it
    reads changed (CompiledGraph.run_frame).
    """

    name = "pass"
    side_effect = False
    keeps_unchanged = False

    def setup(self, builder: "PassBuilder"):  # pragma: no cover - interface
        """Declare reads and writes through ``builder``; return a frozen data object
        holding the handles ``execute`` uses (or None)."""
        raise NotImplementedError

    def execute(self, ctx, data) -> None:  # pragma: no cover - interface
        """Do the work. ``ctx`` resolves only the handles ``setup`` declared."""
        raise NotImplementedError

    def describe(self) -> str:
        """One line of detail for graph dumps (shader features, draw counts...)."""
        return ""


@dataclass
class PassNode:
    """A pass in the graph: what it declared, and the data its setup returned."""

    render_pass: RenderPass
    index: int
    reads: list = field(default_factory=list)
    writes: list = field(default_factory=list)
    own_region_writes: list = field(default_factory=list)  # writes that leave other regions alone
    data: object = None

    @property
    def declared(self) -> frozenset:
        """Resource indices this pass may touch when it executes."""
        return frozenset(h.resource for h in self.reads + self.writes)


@dataclass
class _Resource:
    name: str
    desc: object  # ResourceDesc or InputDesc
    versions: int = 1
    producers: dict = field(default_factory=dict)  # version -> node index

    @property
    def is_input(self) -> bool:
        return isinstance(self.desc, InputDesc)


class PassBuilder:
    """Handed to ``RenderPass.setup``: the only way a pass touches the graph."""

    def __init__(self, graph: "FrameGraph", node: PassNode):
        self._graph = graph
        self._node = node

    def create(self, name: str, desc: ResourceDesc) -> Handle:
        """A new image, written by this pass (version 1)."""
        return self._graph._create(name, desc, self._node)

    def read(self, *handles: Handle) -> None:
        """Declare that this pass reads ``handles`` (inputs or images)."""
        for handle in handles:
            self._graph._check(handle)
            self._node.reads.append(handle)

    def write(self, handle: Handle, *, own_region: bool = False) -> Handle:
        """Draw over ``handle``'s image; returns the new version later passes should read.

        Writing implies reading the previous contents (a pass that draws over an image);
        a pass that replaces everything should ``create`` a fresh image instead.
        ``own_region``: the pass writes only a part of the image no other pass writes
        (a light's tiles of the shadow atlas), so it leaves earlier passes' results as
        they are, and those can stay cached when this pass runs every frame.
        """
        self._graph._check(handle)
        if self._graph._resources[handle.resource].is_input:
            raise ValueError(f"{self._node.render_pass.name} writes {handle}, an input of the world: "
                             "inputs are read-only")
        self._node.reads.append(handle)
        new = self._graph._new_version(handle, self._node)
        if own_region:
            self._node.own_region_writes.append(new)
        return new


class FrameGraph:
    """Passes in submission order plus the resources between them."""

    def __init__(self):
        self._nodes: list[PassNode] = []
        self._resources: list[_Resource] = []

    def import_input(self, name: str, desc: InputDesc) -> Handle:
        """Bring a per-frame value of the world into the graph; passes read it by handle."""
        if any(r.name == name and r.is_input for r in self._resources):
            raise ValueError(f"input {name!r} is already imported")
        self._resources.append(_Resource(name, desc, versions=0))
        return Handle(len(self._resources) - 1, 0, name)

    def is_dynamic(self, handle: Handle) -> bool:
        """Whether an imported input changes over the animation."""
        resource = self._resources[handle.resource]
        if not resource.is_input:
            raise ValueError(f"{handle} is an image; only inputs are static or dynamic by themselves")
        return resource.desc.dynamic

    def add(self, render_pass: RenderPass):
        """Add a pass; its ``setup`` runs now. Returns the data setup returns."""
        node = PassNode(render_pass, len(self._nodes))
        self._nodes.append(node)
        node.data = render_pass.setup(PassBuilder(self, node))
        return node.data

    # -- used by PassBuilder ----------------------------------------------------------
    def _create(self, name: str, desc: ResourceDesc, node: PassNode) -> Handle:
        if not isinstance(desc, ResourceDesc):
            raise TypeError(f"{node.render_pass.name} creates {name} from {desc!r}, not a ResourceDesc")
        resource = _Resource(name, desc)
        self._resources.append(resource)
        handle = Handle(len(self._resources) - 1, 1, name)
        resource.producers[1] = node.index
        node.writes.append(handle)
        return handle

    def _new_version(self, handle: Handle, node: PassNode) -> Handle:
        resource = self._resources[handle.resource]
        if handle.version != resource.versions:
            raise ValueError(f"{node.render_pass.name} writes {handle}, but {resource.name} is already at "
                             f"version {resource.versions}: it must write the latest version")
        resource.versions += 1
        new = Handle(handle.resource, resource.versions, resource.name)
        resource.producers[new.version] = node.index
        node.writes.append(new)
        return new

    def _check(self, handle: Handle) -> None:
        if not isinstance(handle, Handle) or handle.resource >= len(self._resources):
            raise ValueError(f"not a handle of this graph: {handle!r}")

    # -- compile ------------------------------------------------------------------------
    def compile(self) -> "CompiledGraph":
        """Cull passes no side-effect pass depends on; work out which passes are static."""
        needed = self._needed_nodes()
        kept = [n for n in self._nodes if n.index in needed]
        static = self._static_nodes(kept)
        used = {h.resource for n in kept for h in n.reads + n.writes}
        return CompiledGraph(self, kept, [n for n in self._nodes if n.index not in needed], static, used)

    def _producer(self, handle: Handle) -> int | None:
        """The node that wrote this version of an image; None for inputs."""
        return self._resources[handle.resource].producers.get(handle.version)

    def _needed_nodes(self) -> set:
        stack = [n.index for n in self._nodes if n.render_pass.side_effect]
        needed = set()
        while stack:
            index = stack.pop()
            if index in needed:
                continue
            needed.add(index)
            stack.extend(p for p in map(self._producer, self._nodes[index].reads) if p is not None)
        return needed

    def _static_nodes(self, kept: list) -> set:
        """The kept passes that can run once: everything they read is static, and no
        dynamic pass draws over what they wrote (it would draw over its own last frame,
        not over their result). Starts from every pass and drops passes until no rule
        drops one more."""
        drawn_over = self._later_writers(kept)
        static = {n.index for n in kept if not n.render_pass.side_effect}
        changed = True
        while changed:
            keep = {n.index for n in kept if n.index in static
                    and all(self._static_read(h, static) for h in n.reads) and drawn_over[n.index] <= static}
            changed = keep != static
            static = keep
        return static

    def _later_writers(self, kept: list) -> dict:
        """node index -> indices of the kept nodes that draw over a later version of an
        image it writes (not counting writes confined to their own region)."""
        kept_by_index = {n.index: n for n in kept}
        later = {}
        for node in kept:
            found = set()
            for handle in node.writes:
                producers = self._resources[handle.resource].producers
                for version, index in producers.items():
                    writer = kept_by_index.get(index)
                    if version > handle.version and writer is not None \
                            and Handle(handle.resource, version, handle.name) not in writer.own_region_writes:
                        found.add(index)
            later[node.index] = found
        return later

    def _static_read(self, handle: Handle, static: set) -> bool:
        resource = self._resources[handle.resource]
        if resource.is_input:
            return not resource.desc.dynamic
        return self._producer(handle) in static


@dataclass
class CompiledGraph:
    """The passes that will run, in order, and the resources they use."""

    graph: FrameGraph
    passes: list
    culled: list
    static: set
    used_resources: set

    @property
    def pass_names(self) -> list[str]:
        return [n.render_pass.name for n in self.passes]

    @property
    def culled_names(self) -> list[str]:
        return [n.render_pass.name for n in self.culled]

    def resources(self) -> list[tuple[int, str, ResourceDesc]]:
        """The images the kept passes use: (index, name, desc)."""
        return [(i, r.name, r.desc) for i, r in enumerate(self.graph._resources)
                if i in self.used_resources and not r.is_input]

    def inputs(self) -> list[tuple[int, str, InputDesc]]:
        """The world inputs the kept passes read: (index, name, desc)."""
        return [(i, r.name, r.desc) for i, r in enumerate(self.graph._resources)
                if i in self.used_resources and r.is_input]

    def is_static(self, render_pass: RenderPass) -> bool:
        return any(n.render_pass is render_pass and n.index in self.static for n in self.passes)

    def node(self, name: str) -> PassNode:
        """The kept pass called ``name``."""
        for node in self.passes:
            if node.render_pass.name == name:
                return node
        raise KeyError(f"no kept pass named {name!r}; kept: {', '.join(self.pass_names)}")

    def readers(self, input_name: str) -> list[str]:
        """Names of the kept passes that read the input ``input_name``."""
        return [n.render_pass.name for n in self.passes
                if any(h.version == 0 and h.name == input_name for h in n.reads)]

    def run_frame(self, backend, frame, first: bool) -> None:
        """Execute this frame's passes through ``backend``: static passes only on the first
        frame, and a pass that keeps unchanged results (RenderPass.keeps_unchanged) only
        when something it reads changed: an image drawn into earlier this frame, or a
        dynamic input whose value ``backend.same_input(node, handle)`` finds different from
        the one the pass last ran with. ``backend.execute(node, frame, written)`` gets the
        images drawn into so far this frame."""
        written: set = set()
        for node in self.passes:
            if not first and (node.index in self.static or self._unchanged(node, backend, written)):
                continue
            backend.execute(node, frame, written)
            written.update(h.resource for h in node.writes)

    def _unchanged(self, node: PassNode, backend, written: set) -> bool:
        if not node.render_pass.keeps_unchanged:
            return False
        for handle in node.reads:
            resource = self.graph._resources[handle.resource]
            if resource.is_input:
                if resource.desc.dynamic and not backend.same_input(node, handle):
                    return False
            elif handle.resource in written:
                return False
        return True

    # -- dumps -------------------------------------------------------------------------
    def dump(self) -> str:
        """A readable listing: inputs, passes with their reads/writes, culled passes, images."""
        lines = ["inputs:"]
        for _, name, desc in self.inputs():
            lines.append(f"  {name:<22} {desc.describe()}".rstrip())
        lines.append(f"passes ({len(self.passes)} kept, {len(self.culled)} culled):")
        for i, node in enumerate(self.passes, 1):
            tag = "static " if node.index in self.static else ("output " if node.render_pass.side_effect else "dynamic")
            detail = node.render_pass.describe()
            lines.append(f"  {i:2d}. {node.render_pass.name:<22} {tag}  {detail}".rstrip())
            inputs = [str(h) for h in node.reads if h.version == 0]
            reads = [str(h) for h in node.reads if h.version > 0 and h not in node.writes]
            if inputs:
                lines.append(f"        inputs {', '.join(inputs)}")
            if reads:
                lines.append(f"        reads  {', '.join(reads)}")
            if node.writes:
                lines.append(f"        writes {', '.join(str(h) for h in node.writes)}")
        if self.culled:
            lines.append("culled (no output needs them): " + ", ".join(self.culled_names))
        lines.append("images:")
        for index, name, desc in self.resources():
            lines.append(f"  {name:<18} {desc.describe()}")
        return "\n".join(lines)

    def dot(self) -> str:
        """Graphviz: passes are boxes, images ellipses, inputs diamonds; culled passes grey."""
        out = ["digraph rendergraph {", "  rankdir=LR;", '  node [fontname="Helvetica", fontsize=10];']
        kept = {n.index for n in self.passes}
        for index, name, desc in self.inputs():
            color = "lightyellow" if desc.dynamic else "lightblue"
            out.append(f'  r{index}_0 [shape=diamond, style=filled, fillcolor={color}, label="{name}"];')
        for node in self.graph._nodes:
            style = "filled" if node.index in kept else "dashed"
            color = ("lightblue" if node.index in self.static else "lightyellow") if node.index in kept else "grey"
            out.append(f'  p{node.index} [shape=box, style={style}, fillcolor={color}, color={color if style == "dashed" else "black"}, '
                       f'label="{node.render_pass.name}"];')
            for handle in node.reads:
                if handle not in node.writes and (handle.version > 0 or node.index in kept):
                    out.append(f'  r{handle.resource}_{handle.version} -> p{node.index};')
            for handle in node.writes:
                out.append(f'  r{handle.resource}_{handle.version} [shape=ellipse, label="{handle}"];')
                out.append(f'  p{node.index} -> r{handle.resource}_{handle.version};')
        out.append("}")
        return "\n".join(out)
