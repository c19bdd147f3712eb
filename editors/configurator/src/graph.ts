// The computation graph of the remaining products, HAROS-style (ROS nodes white, topics green,
// parameters purple, services blue; elements not in every remaining product dashed).
// The layout is computed ONCE, by ELK (elkjs, layered), on the graph of all products: a click
// then only changes classes (solid / dashed / hidden), so nothing else ever moves -- the thesis's
// complaint about HAROS, where each configuration got a layout of its own.
import ELK from 'elkjs/lib/elk-api.js';
import type { ElkExtendedEdge, ElkNode } from 'elkjs/lib/elk-api';
import { select, Selection } from 'd3-selection';
import { zoom as d3zoom, zoomIdentity, ZoomBehavior, ZoomTransform } from 'd3-zoom';
import type { GraphEdge, GraphElement, GraphJson, Status } from './types';

const SVGNS = 'http://www.w3.org/2000/svg';

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

export class GraphView {
  private svg: Selection<SVGSVGElement, unknown, null, undefined>;
  private layer: Selection<SVGGElement, unknown, null, undefined>;
  private zoom: ZoomBehavior<SVGSVGElement, unknown>;
  private placed = new Map<string, Placed>();
  private ready: Promise<void>;
  private statuses: Record<string, Status> = {};
  private selected: string | null = null;
  showRemoved = false;

  constructor(private host: HTMLElement, private graph: GraphJson, private handlers: GraphHandlers,
    private makeWorker: () => Promise<Worker>) {
    this.svg = select(host).append('svg').attr('class', 'graph')
      .attr('aria-label', 'computation graph') as unknown as Selection<SVGSVGElement, unknown, null, undefined>;
    const defs = this.svg.append('defs');
    defs.append('marker').attr('id', 'arrow').attr('viewBox', '0 0 10 10').attr('refX', 9).attr('refY', 5)
      .attr('markerWidth', 7).attr('markerHeight', 7).attr('orient', 'auto-start-reverse')
      .append('path').attr('d', 'M0,0 L10,5 L0,10 z').attr('class', 'arrowhead');
    this.layer = this.svg.append('g').attr('class', 'layer');
    this.zoom = d3zoom<SVGSVGElement, unknown>().scaleExtent([0.1, 3])
      .on('zoom', (ev: { transform: ZoomTransform }) => this.layer.attr('transform', ev.transform.toString()));
    this.svg.call(this.zoom).on('dblclick.zoom', null);
    this.ready = graph.elements.length
      ? this.layout().catch((e: Error) => this.failed(e))
      : Promise.resolve(this.empty());
  }

  private empty(): void {
    select(this.host).append('div').attr('class', 'empty')
      .text('No computation graph: this model configures no launch file (pair one through a HAROS project file, a marker comment or the same name).');
  }

  private failed(e: Error): void {
    select(this.host).append('div').attr('class', 'empty').text(`The graph layout failed: ${e.message}`);
  }

  private async layout(): Promise<void> {
    // ELK runs in a Web Worker: the page paints the feature diagram meanwhile
    const worker = await this.makeWorker();
    const elk = new ELK({ workerFactory: () => worker });
    const ids = new Set(this.graph.elements.map((e) => e.id));
    const input = (direction: string): ElkNode => ({
      id: 'root',
      layoutOptions: {
        'elk.algorithm': 'layered',
        'elk.direction': direction,
        'elk.spacing.nodeNode': '20',
        'elk.layered.spacing.nodeNodeBetweenLayers': '40',
        'elk.edgeRouting': 'POLYLINE',
        'elk.layered.considerModelOrder.strategy': 'NODES_AND_EDGES',
        'elk.separateConnectedComponents': 'true',
        'elk.spacing.componentComponent': '28',
        'elk.randomSeed': '1',
      },
      children: this.graph.elements.map((e) => ({ id: e.id, ...toWH(size(e)) })),
      edges: this.graph.edges
        .filter((e) => ids.has(e.source) && ids.has(e.target))
        .map((e) => ({ id: e.id, sources: [e.source], targets: [e.target] }) as ElkExtendedEdge),
    });
    // left to right as HAROS draws it, or top-down when that fits the panel better (decided
    // once, at load: the layout never changes afterwards)
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
    for (const c of out.children ?? []) {
      this.placed.set(c.id, { x: c.x ?? 0, y: c.y ?? 0, w: c.width ?? 0, h: c.height ?? 0 });
    }
    const routes = new Map<string, string>();
    for (const e of (out.edges ?? []) as ElkExtendedEdge[]) {
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
    this.draw(routes, out.width ?? 0, out.height ?? 0);
  }

  private draw(routes: Map<string, string>, width: number, height: number): void {
    const edges = this.layer.append('g').attr('class', 'edges');
    for (const e of this.graph.edges) {
      const d = routes.get(e.id);
      if (!d) {
        continue;
      }
      const g = edges.append('g').attr('class', `edge kind-${e.kind}`).attr('data-id', e.id);
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
      g.append('text').attr('x', p.w / 2).attr('y', p.h / 2).attr('dy', '0.35em').attr('text-anchor', 'middle')
        .text(e.label.length > 40 ? e.label.slice(0, 39) + '…' : e.label);
      const title = document.createElementNS(SVGNS, 'title');
      title.textContent = `${e.kind} ${e.name}` + (e.condition ? `\nwhen ${e.condition}` : '\nin every product');
      g.node()?.appendChild(title);
      g.on('click', () => this.pick(e.id, e, 'element'))
        .on('keydown', (ev: KeyboardEvent) => ev.key === 'Enter' && this.pick(e.id, e, 'element'));
    }
    this.fit(width, height);
    this.restyle();
  }

  private pick(id: string, e: GraphElement | GraphEdge, kind: 'element' | 'edge'): void {
    this.selected = id;
    this.restyle();
    this.handlers.select(e, kind);
  }

  private fit(width: number, height: number): void {
    const box = this.host.getBoundingClientRect();
    if (!box.width || !box.height || !width || !height) {
      return;
    }
    const k = Math.max(0.2, Math.min(1.4, (box.width - 24) / width, (box.height - 24) / height));
    this.svg.call(this.zoom.transform,
      zoomIdentity.translate((box.width - k * width) / 2, (box.height - k * height) / 2).scale(k));
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
    this.layer.selectAll<SVGGElement, unknown>('g.element, g.edge').each((_, i, groups) => {
      const g = select(groups[i]);
      const id = g.attr('data-id');
      const st = this.status(id);
      g.classed('st-certain', st === 'certain').classed('st-possible', st === 'possible')
        .classed('st-absent', st === 'absent').classed('ghost', st === 'absent' && this.showRemoved)
        .classed('selected', id === this.selected)
        .attr('data-status', st);
    });
  }

  /** Where an element is drawn (tests check that clicks never move anything). */
  position(id: string): Placed | undefined {
    return this.placed.get(id);
  }
}

function toWH(s: { w: number; h: number }): { width: number; height: number } {
  return { width: s.w, height: s.h };
}
