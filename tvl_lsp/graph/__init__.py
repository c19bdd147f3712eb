"""The variability-aware computation graph (issue #16).  Pure: no LSP here.

    hints = parse_hints(project_path, project_text)            # HAROS `nodes:` hints
    ex = sources.extract([workspace])                           # what the nodes' sources use
    graph = build_graph(launch_analysis, hints, sources=ex.by_node_type())  # every product at once
    logic = GraphLogic(encoding, free_args, model_analysis)      # the products (model + free args)
    g = project(graph, logic, {"Teleop": True}, count=True)     # the remaining products
    to_json(g) / to_dot(g) / to_mermaid(g)
    graph_diagnostics(graph, logic, launch_analysis)            # topic-without-publisher, ...

``build_product_graph(load_result, hints)`` builds one product's graph from the concrete load
(what roslaunch loads for one assignment): the projection of the symbolic graph on a complete
product equals it.
"""

from .build import build_graph, build_product_graph
from .checks import graph_diagnostics
from .hints import HintEntry, NodeHints, ProjectHints, parse_hints
from .model import Graph, GraphNode, Link, Location, Resource, Via
from .names import resolve, resolve_remapped
from .logic import GraphLogic
from .project import NoProducts, UnknownFeature, project
from .render import to_dot, to_json, to_mermaid, view

__all__ = ["build_graph", "build_product_graph", "graph_diagnostics", "HintEntry", "NodeHints",
           "ProjectHints", "parse_hints", "Graph", "GraphNode", "Link", "Location", "Resource", "Via",
           "resolve", "resolve_remapped", "GraphLogic", "NoProducts", "UnknownFeature", "project",
           "to_dot", "to_json", "to_mermaid", "view"]
