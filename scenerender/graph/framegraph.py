"""The frame graph: passes, versioned resource handles, culling, caching, dumps.

Each pass has a ``setup(builder)`` that declares what it reads and writes and an
``execute(ctx)`` that does the GL work. Writing a resource creates a new *version* of its
handle, so "skybox draws over the opaque colour" is an explicit edge: the skybox reads
version 1 and writes version 2. Compiling walks back from the passes with side effects
(the readback) and drops every pass nothing needs.

A pass is *static* when its own inputs never change over the animation (``pass.dynamic``
is False) and every pass it reads from is static: it then executes once and its results
stay in place for all later frames.
"""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class ResourceDesc:
    """What a GPU resource is; the backend allocates it once per run.

    kind:    "color" | "depth" (textures) or "buffer".
    size:    (width, height) in texels.
    format:  "rgba8" | "rgba16f" | "rg16f" | "r8" | "r16f" | "depth24" | "depth32f" | "camera_depth"
             (the device's choice, gpu.depth).
    samples: MSAA sample count; 0 or 1 means single-sampled (a texture), more means a
             multisampled renderbuffer that must be resolved before sampling.
    """

    kind: str
    size: tuple
    format: str
    samples: int = 0

    def describe(self) -> str:
        text = f"{self.kind} {self.format} {self.size[0]}x{self.size[1]}"
        return text + (f" x{self.samples} MSAA" if self.samples > 1 else "")


@dataclass(frozen=True)
class Handle:
    """A versioned reference to a graph resource; passes only ever hold handles."""

    resource: int
    version: int
    name: str

    def __str__(self) -> str:
        return f"{self.name}#{self.version}"


class RenderPass:
    """Base class of every pass. Subclasses set ``name`` and implement setup/execute.

    ``dynamic``: True when the pass must run again on every frame even if its inputs did
    not change (it depends on animated values or the camera).
    ``side_effect``: True for passes whose work leaves the graph (readback to a sink).
    """

    name = "pass"
    dynamic = True
    side_effect = False

    def setup(self, builder: "PassBuilder") -> None:  # pragma: no cover - interface
        raise NotImplementedError

    def execute(self, ctx) -> None:  # pragma: no cover - interface
        raise NotImplementedError

    def describe(self) -> str:
        """One line of detail for graph dumps (shader features, draw counts...)."""
        return ""


@dataclass
class _Node:
    render_pass: RenderPass
    index: int
    reads: list = field(default_factory=list)
    writes: list = field(default_factory=list)
    creates: list = field(default_factory=list)


@dataclass
class _Resource:
    name: str
    desc: ResourceDesc
    versions: int = 1
    producers: dict = field(default_factory=dict)  # version -> node index


class PassBuilder:
    """Handed to ``RenderPass.setup``: the only way a pass touches the graph."""

    def __init__(self, graph: "FrameGraph", node: _Node):
        self._graph = graph
        self._node = node

    def create(self, name: str, desc: ResourceDesc) -> Handle:
        """A new resource, written by this pass (version 1)."""
        return self._graph._create(name, desc, self._node)

    def read(self, handle: Handle) -> Handle:
        self._graph._check(handle)
        self._node.reads.append(handle)
        return handle

    def write(self, handle: Handle) -> Handle:
        """Write ``handle``'s resource; returns the new version later passes should read.

        Writing implies reading the previous contents (a pass that draws over an image);
        a pass that replaces everything should ``create`` a fresh resource instead.
        """
        self._graph._check(handle)
        self._node.reads.append(handle)
        return self._graph._new_version(handle, self._node)


class FrameGraph:
    """Passes in submission order plus the resources between them."""

    def __init__(self):
        self._nodes: list[_Node] = []
        self._resources: list[_Resource] = []

    def add(self, render_pass: RenderPass):
        """Add a pass; its ``setup`` runs now. Returns whatever setup returns (its outputs)."""
        node = _Node(render_pass, len(self._nodes))
        self._nodes.append(node)
        return render_pass.setup(PassBuilder(self, node))

    # -- used by PassBuilder ----------------------------------------------------------
    def _create(self, name: str, desc: ResourceDesc, node: _Node) -> Handle:
        resource = _Resource(name, desc)
        self._resources.append(resource)
        handle = Handle(len(self._resources) - 1, 1, name)
        resource.producers[1] = node.index
        node.creates.append(handle)
        node.writes.append(handle)
        return handle

    def _new_version(self, handle: Handle, node: _Node) -> Handle:
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

    def _producer(self, handle: Handle) -> int:
        return self._resources[handle.resource].producers[handle.version]

    def _needed_nodes(self) -> set:
        stack = [n.index for n in self._nodes if n.render_pass.side_effect]
        needed = set()
        while stack:
            index = stack.pop()
            if index in needed:
                continue
            needed.add(index)
            for handle in self._nodes[index].reads:
                stack.append(self._producer(handle))
        return needed

    def _static_nodes(self, kept: list) -> set:
        static = set()
        for node in kept:  # submission order is a topological order
            inputs_static = all(self._producer(h) in static for h in node.reads)
            if not node.render_pass.dynamic and not node.render_pass.side_effect and inputs_static:
                static.add(node.index)
        return static


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
        return [(i, r.name, r.desc) for i, r in enumerate(self.graph._resources) if i in self.used_resources]

    def is_static(self, render_pass: RenderPass) -> bool:
        return any(n.render_pass is render_pass and n.index in self.static for n in self.passes)

    def run_frame(self, backend, frame, first: bool) -> None:
        """Execute this frame's passes through ``backend``: static passes only on the first frame."""
        for node in self.passes:
            if first or node.index not in self.static:
                backend.execute(node.render_pass, frame)

    # -- dumps -------------------------------------------------------------------------
    def dump(self) -> str:
        """A readable listing: passes with their reads/writes, culled passes, resources."""
        lines = [f"passes ({len(self.passes)} kept, {len(self.culled)} culled):"]
        for i, node in enumerate(self.passes, 1):
            tag = "static " if node.index in self.static else ("output " if node.render_pass.side_effect else "dynamic")
            detail = node.render_pass.describe()
            lines.append(f"  {i:2d}. {node.render_pass.name:<22} {tag}  {detail}".rstrip())
            reads = [str(h) for h in node.reads if h not in node.writes]
            if reads:
                lines.append(f"        reads  {', '.join(reads)}")
            if node.writes:
                lines.append(f"        writes {', '.join(str(h) for h in node.writes)}")
        if self.culled:
            lines.append("culled (no output needs them): " + ", ".join(self.culled_names))
        lines.append("resources:")
        for index, name, desc in self.resources():
            lines.append(f"  {name:<18} {desc.describe()}")
        return "\n".join(lines)

    def dot(self) -> str:
        """Graphviz: passes are boxes, resource versions ellipses; culled passes grey."""
        out = ["digraph rendergraph {", "  rankdir=LR;", '  node [fontname="Helvetica", fontsize=10];']
        kept = {n.index for n in self.passes}
        for node in self.graph._nodes:
            style = "filled" if node.index in kept else "dashed"
            color = ("lightblue" if node.index in self.static else "lightyellow") if node.index in kept else "grey"
            out.append(f'  p{node.index} [shape=box, style={style}, fillcolor={color}, color={color if style == "dashed" else "black"}, '
                       f'label="{node.render_pass.name}"];')
            for handle in node.reads:
                if handle not in node.writes:
                    out.append(f'  r{handle.resource}_{handle.version} -> p{node.index};')
            for handle in node.writes:
                out.append(f'  r{handle.resource}_{handle.version} [shape=ellipse, label="{handle}"];')
                out.append(f'  p{node.index} -> r{handle.resource}_{handle.version};')
        out.append("}")
        return "\n".join(out)
