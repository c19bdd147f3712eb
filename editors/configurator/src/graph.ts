// The computation graph of the remaining products, HAROS-style (ROS nodes white, topics green,
// parameters purple, services blue; elements not in every remaining product dashed; includes of
// packages outside the workspace as grey placeholders with their condition).
// The layout is computed by ELK (elkjs, layered) on the graph of all products: a click then only
// changes classes (solid / dashed / hidden), so nothing ever moves -- the thesis's complaint about
// HAROS, where each configuration got a layout of its own. Grouping by namespace lays it out once
// more (namespaces as boxes); fit, zoom, search and a filter by kind change no position either.
import ELK from 'elkjs/lib/elk-api.js';
import type { ElkExtendedEdge, ElkNode } from 'elkjs/lib/elk-api';
import { select, Selection } from 'd3-selection';
import 'd3-transition';
import { zoom as d3zoom, zoomIdentity, ZoomBehavior, ZoomTransform } from 'd3-zoom';
import { zoomControls, zoomKeys } from './diagram';
import type { GraphEdge, GraphElement, GraphJson, Status } from './types';

const SVGNS = 'http://www.w3.org/2000/svg';
export const KINDS = ['node', 'topic', 'service', 'param', 'include'];

export interface GraphHandlers {
  select(e: GraphElement | GraphEdge, kind: 'element' | 'edge'): void;
}

interface Placed {
  x: number;
  y: number;
  w: number;
  h: number;
}

function size(e: GraphElement): { w: number; h: number } {
  const chars = Math.min(Math.max(e.label.length, 4), 40);
  return { w: Math.round(chars * 7.4 + 28), h: e.kind === 'node' ? 40 : 30 };
}

/** The namespace an element is drawn in when grouping: a node's namespace, a resource's prefix. */
export function namespaceOf(e: GraphElement): string {
  if (e.kind === 'include') {
    return '(not followed)';
  }
  const ns = e.kind === 'node' ? String((e.details ?? {}).namespace ?? '') : '';
  if (ns) {
    return ns.endsWith('/') && ns.length > 1 ? ns.slice(0, -1) : ns;
  }
  const name = e.name.startsWith('/') ? e.name : '/' + e.name;
  const i = name.lastIndexOf('/');
  return i > 0 ? name.slice(0, i) : '/';
}

export class GraphView {
  private svg: Selection<SVGSVGElement, unknown, null, undefined>;
  private layer: Selection<SVGGElement, unknown, null, undefined>;
  private zoom: ZoomBehavior<SVGSVGElement, unknown>;
  private placed = new Map<string, Placed>();
  private ready: Promise<void>;
  private statuses: Record<string, Status> = {};
  private selected: string | null = null;
  private linked = new Set<string>();
  private matches = new Set<string>();
  private hiddenKinds = new Set<string>();
  private extent = { width: 0, height: 0 };
  private byId = new Map<string, GraphElement>();
  private grouped = false;
  private resize: ResizeObserver;
  private autoFit = true;
  private fitting = false;
  private lastSize = '';
  showRemoved = false;

  constructor(private host: HTMLElement, private graph: GraphJson, private handlers: GraphHandlers,
    private makeWorker: () => Promise<Worker>) {
    graph.elements.forEach((e) => this.byId.set(e.id, e));
    this.svg = select(host).append('svg').attr('class', 'graph').attr('tabindex', '0')
      .attr('aria-label', 'computation graph (f: fit, +/-: zoom)') as unknown as Selection<SVGSVGElement, unknown, null, undefined>;
    const defs = this.svg.append('defs');
    defs.append('marker').attr('id', 'arrow').attr('viewBox', '0 0 10 10').attr('refX', 9).attr('refY', 5)
      .attr('markerWidth', 7).attr('markerHeight', 7).attr('orient', 'auto-start-reverse')
      .append('path').attr('d', 'M0,0 L10,5 L0,10 z').attr('class', 'arrowhead');
    this.layer = this.svg.append('g').attr('class', 'layer');
    this.zoom = d3zoom<SVGSVGElement, unknown>().scaleExtent([0.05, 3])
      .on('zoom', (ev: { transform: ZoomTransform; sourceEvent: Event | null }) => {
        this.layer.attr('transform', ev.transform.toString());
        if (ev.sourceEvent && !this.fitting) {
          this.autoFit = false;
        }
      });
    this.svg.call(this.zoom).on('dblclick.zoom', null);
    this.svg.on('keydown', (ev: KeyboardEvent) => zoomKeys(ev, () => this.fit(), (k) => this.zoomBy(k)));
    this.ready = graph.elements.length
      ? this.layout().catch((e: Error) => this.failed(e))
      : Promise.resolve(this.empty());
    if (graph.elements.length) {
      zoomControls(host, () => this.fit(), (k) => this.zoomBy(k));
    }
    this.resize = new ResizeObserver(() => {
      const b = this.host.getBoundingClientRect();
      const s = `${Math.round(b.width)}x${Math.round(b.height)}`;
      if (s !== this.lastSize && b.width && b.height) {
        this.lastSize = s;
        if (this.autoFit) {
          this.fit(false);
        }
      }
    });
    this.resize.observe(host);
  }

  private empty(): void {
    select(this.host).append('div').attr('class', 'empty')
      .text('The launch file starts no node, sets no parameter and includes nothing tvl-lsp could not follow.');
  }

  private failed(e: Error): void {
    select(this.host).append('div').attr('class', 'empty').text(`The graph layout failed: ${e.message}`);
  }

  private async layout(): Promise<void> {
    // ELK runs in a Web Worker: the page paints the feature diagram meanwhile
    const worker = await this.makeWorker();
    const elk = new ELK({ workerFactory: () => worker });
    const ids = new Set(this.graph.elements.map((e) => e.id));
    const hb = this.host.getBoundingClientRect();
    const aspect = hb.width && hb.height ? hb.width / hb.height : 1.6;
    const options = (direction: string): Record<string, string> => ({
      'elk.algorithm': 'layered',
      'elk.direction': direction,
      'elk.spacing.nodeNode': '20',
      'elk.layered.spacing.nodeNodeBetweenLayers': '40',
      'elk.edgeRouting': 'POLYLINE',
      'elk.layered.considerModelOrder.strategy': 'NODES_AND_EDGES',
      'elk.separateConnectedComponents': 'true',
      'elk.spacing.componentComponent': '28',
      'elk.aspectRatio': String(Math.max(0.5, Math.min(4, aspect))),
      'elk.randomSeed': '1',
      'elk.json.shapeCoords': 'ROOT',
      'elk.json.edgeCoords': 'ROOT',
    });
    const edges = this.graph.edges
      .filter((e) => ids.has(e.source) && ids.has(e.target))
      .map((e) => ({ id: e.id, sources: [e.source], targets: [e.target] }) as ElkExtendedEdge);
    const leaf = (e: GraphElement): ElkNode => ({ id: e.id, ...toWH(size(e)) });
    const input = (direction: string): ElkNode => {
      if (!this.grouped) {
        return { id: 'root', layoutOptions: options(direction), children: this.graph.elements.map(leaf), edges };
      }
      const groups = new Map<string, GraphElement[]>();
      for (const e of this.graph.elements) {
        const ns = namespaceOf(e);
        groups.set(ns, [...(groups.get(ns) ?? []), e]);
      }
      const children: ElkNode[] = [...groups.entries()].map(([ns, els]) => ({
        id: `ns:${ns}`, labels: [{ text: ns, width: ns.length * 7 + 10, height: 14 }],
        layoutOptions: { 'elk.padding': '[top=26,left=10,bottom=10,right=10]', 'elk.nodeLabels.placement': 'INSIDE V_TOP H_LEFT' },
        children: els.map(leaf),
      }));
      const opts = { ...options(direction), 'elk.hierarchyHandling': 'INCLUDE_CHILDREN' };
      return { id: 'root', layoutOptions: opts, children, edges };
    };
    // left to right as HAROS draws it, or top-down when that fits the panel better (decided
    // once per layout: statuses never change it)
    const box = this.host.getBoundingClientRect();
    const scale = (g: ElkNode) => Math.min((box.width || 600) / (g.width || 1), (box.height || 400) / (g.height || 1));
    let out = await elk.layout(input('RIGHT'));
    if (this.graph.elements.length <= 400) {
      const down = await elk.layout(input('DOWN'));
      if (scale(down) > 1.15 * scale(out)) {
        out = down;
      }
    }
    elk.terminateWorker();
    this.placed.clear();
    const groups: { id: string; p: Placed }[] = [];
    const walk = (n: ElkNode) => {
      for (const c of n.children ?? []) {
        const p = { x: c.x ?? 0, y: c.y ?? 0, w: c.width ?? 0, h: c.height ?? 0 };
        if (c.id.startsWith('ns:')) {
          groups.push({ id: c.id, p });
          walk(c);
        } else {
          this.placed.set(c.id, p);
        }
      }
    };
    walk(out);
    const routes = new Map<string, string>();
    const collect = (n: ElkNode) => {
      for (const e of (n.edges ?? []) as ElkExtendedEdge[]) {
        const pts: string[] = [];
        for (const s of e.sections ?? []) {
          pts.push(`${s.startPoint.x},${s.startPoint.y}`);
          for (const b of s.bendPoints ?? []) {
            pts.push(`${b.x},${b.y}`);
          }
          pts.push(`${s.endPoint.x},${s.endPoint.y}`);
        }
        routes.set(e.id, 'M' + pts.join(' L'));
      }
      (n.children ?? []).forEach(collect);
    };
    collect(out);
    this.draw(routes, groups, out.width ?? 0, out.height ?? 0);
  }

  private draw(routes: Map<string, string>, groups: { id: string; p: Placed }[], width: number, height: number): void {
    this.layer.selectAll('*').remove();
    const boxes = this.layer.append('g').attr('class', 'namespaces');
    for (const g of groups) {
      const b = boxes.append('g').attr('class', 'namespace').attr('data-id', g.id);
      b.append('rect').attr('x', g.p.x).attr('y', g.p.y).attr('width', g.p.w).attr('height', g.p.h).attr('rx', 6);
      b.append('text').attr('x', g.p.x + 8).attr('y', g.p.y + 16).text(g.id.slice(3));
    }
    const edges = this.layer.append('g').attr('class', 'edges');
    for (const e of this.graph.edges) {
      const d = routes.get(e.id);
      if (!d) {
        continue;
      }
      const g = edges.append('g').attr('class', `edge kind-${e.kind}`).attr('data-id', e.id)
        .attr('data-source', e.source).attr('data-target', e.target);
      g.append('path').attr('class', 'hit').attr('d', d);
      g.append('path').attr('class', 'line').attr('d', d)
        .attr('marker-end', e.kind === 'uses' ? null : 'url(#arrow)');
      g.append('title').text(`${e.kind}: ${e.source.replace(/^\w+:/, '')} → ${e.target.replace(/^\w+:/, '')}` +
        (e.condition ? `\nwhen ${e.condition}` : ''));
      g.on('click', () => this.pick(e.id, e, 'edge'));
    }
    const nodes = this.layer.append('g').attr('class', 'elements');
    for (const e of this.graph.elements) {
      const p = this.placed.get(e.id);
      if (!p) {
        continue;
      }
      const g = nodes.append('g').attr('class', `element kind-${e.kind}`).attr('data-id', e.id)
        .attr('data-kind', e.kind).attr('transform', `translate(${p.x},${p.y})`).attr('tabindex', '0');
      if (e.kind === 'node') {
        g.append('ellipse').attr('class', 'shape').attr('cx', p.w / 2).attr('cy', p.h / 2)
          .attr('rx', p.w / 2).attr('ry', p.h / 2);
      } else {
        g.append('rect').attr('class', 'shape').attr('width', p.w).attr('height', p.h)
          .attr('rx', e.kind === 'param' ? 12 : 3);
      }
      const label = e.kind === 'include' ? `⇢ ${e.label}` : e.label;
      g.append('text').attr('x', p.w / 2).attr('y', p.h / 2).attr('dy', '0.35em').attr('text-anchor', 'middle')
        .text(label.length > 40 ? label.slice(0, 39) + '…' : label);
      const title = document.createElementNS(SVGNS, 'title');
      title.textContent = `${e.kind === 'include' ? 'include (not followed)' : e.kind} ${e.name}` +
        (e.condition ? `\nwhen ${e.condition}` : '\nin every product');
      g.node()?.appendChild(title);
      g.on('click', () => this.pick(e.id, e, 'element'))
        .on('keydown', (ev: KeyboardEvent) => ev.key === 'Enter' && this.pick(e.id, e, 'element'));
    }
    this.extent = { width, height };
    this.fit(false);
    this.restyle();
  }

  private pick(id: string, e: GraphElement | GraphEdge, kind: 'element' | 'edge'): void {
    this.selected = id;
    this.restyle();
    this.handlers.select(e, kind);
  }

  /** Select an element by id (from the details panel or a feature's links) and bring it into view. */
  show(id: string): void {
    const e = this.byId.get(id);
    if (!e) {
      return;
    }
    this.selected = id;
    this.restyle();
    this.centre([id]);
  }

  /** Fit the laid-out graph in the panel. */
  fit(animate = true): void {
    const box = this.host.getBoundingClientRect();
    const { width, height } = this.extent;
    if (!box.width || !box.height || !width || !height) {
      return;
    }
    const bw = box.width - 40; // the zoom buttons keep the right edge
    const k = Math.max(0.05, Math.min(1.4, (bw - 24) / width, (box.height - 24) / height));
    const to = zoomIdentity.translate((bw - k * width) / 2, (box.height - k * height) / 2).scale(k);
    this.autoFit = true;
    this.fitting = true;
    if (animate) {
      this.svg.transition().duration(250).call(this.zoom.transform, to).on('end', () => { this.fitting = false; });
    } else {
      this.svg.call(this.zoom.transform, to);
      this.fitting = false;
    }
  }

  zoomBy(factor: number): void {
    this.autoFit = false;
    this.svg.transition().duration(150).call(this.zoom.scaleBy, factor);
  }

  private centre(ids: string[]): void {
    const ps = ids.map((i) => this.placed.get(i)).filter((p): p is Placed => !!p);
    if (!ps.length) {
      return;
    }
    const box = this.host.getBoundingClientRect();
    const t = (this.svg.node() as SVGSVGElement & { __zoom?: ZoomTransform }).__zoom ?? zoomIdentity;
    const cx = (Math.min(...ps.map((p) => p.x)) + Math.max(...ps.map((p) => p.x + p.w))) / 2;
    const cy = (Math.min(...ps.map((p) => p.y)) + Math.max(...ps.map((p) => p.y + p.h))) / 2;
    const k = Math.max(t.k, 0.6);
    this.autoFit = false;
    this.svg.transition().duration(300).call(this.zoom.transform,
      zoomIdentity.translate(box.width / 2 - k * cx, box.height / 2 - k * cy).scale(k));
  }

  /** Elements whose name contains the query: marked, the first brought into view; their ids. */
  search(query: string): string[] {
    const q = query.trim().toLowerCase();
    this.matches = new Set(q ? this.graph.elements.filter((e) => e.name.toLowerCase().includes(q)).map((e) => e.id) : []);
    this.restyle();
    const ids = [...this.matches];
    if (ids.length) {
      this.centre(ids.slice(0, 1));
    }
    return ids;
  }

  setHiddenKinds(kinds: Set<string>): void {
    this.hiddenKinds = kinds;
    this.restyle();
  }

  async setGrouped(on: boolean): Promise<void> {
    if (on === this.grouped) {
      return;
    }
    this.grouped = on;
    await this.ready;
    this.ready = this.layout().catch((e: Error) => this.failed(e));
    await this.ready;
  }

  /** Elements linked to the selected feature (its presence conditions mention it). */
  setLinked(ids: Set<string>): void {
    this.linked = ids;
    this.restyle();
  }

  async setStatus(status: Record<string, Status>): Promise<void> {
    this.statuses = status;
    await this.ready;
    this.restyle();
  }

  whenReady(): Promise<void> {
    return this.ready;
  }

  status(id: string): Status {
    return this.statuses[id] ?? 'possible';
  }

  restyle(): void {
    // a namespace box all of whose elements the decisions removed is faded too
    const alive = new Set<string>();
    for (const e of this.graph.elements) {
      if (this.status(e.id) !== 'absent' || this.showRemoved) alive.add(`ns:${namespaceOf(e)}`);
    }
    this.layer.selectAll<SVGGElement, unknown>('g.namespace').each((_, i, groups) => {
      const g = select(groups[i]);
      g.classed('empty', !alive.has(g.attr('data-id')));
    });
    this.layer.selectAll<SVGGElement, unknown>('g.element, g.edge').each((_, i, groups) => {
      const g = select(groups[i]);
      const id = g.attr('data-id');
      const st = this.status(id);
      const kind = g.attr('data-kind') ?? this.byId.get(g.attr('data-source'))?.kind;
      const filtered = g.classed('edge')
        ? this.hiddenKinds.has(this.byId.get(g.attr('data-source'))?.kind ?? '') ||
          this.hiddenKinds.has(this.byId.get(g.attr('data-target'))?.kind ?? '')
        : this.hiddenKinds.has(kind ?? '');
      g.classed('st-certain', st === 'certain').classed('st-possible', st === 'possible')
        .classed('st-absent', st === 'absent').classed('ghost', st === 'absent' && this.showRemoved)
        .classed('selected', id === this.selected)
        .classed('linked', this.linked.has(id))
        .classed('match', this.matches.has(id))
        .classed('filtered', filtered)
        .attr('data-status', st);
    });
  }

  /** Where an element is drawn (tests check that clicks never move anything). */
  position(id: string): Placed | undefined {
    return this.placed.get(id);
  }

  destroy(): void {
    this.resize.disconnect();
  }
}

function toWH(s: { w: number; h: number }): { width: number; height: number } {
  return { width: s.w, height: s.h };
}
