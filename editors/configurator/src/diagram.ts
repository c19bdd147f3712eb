// The feature diagram, drawn as the thesis drew it (Figures 17 and 19): a top-down tree of
// rectangles with the group kind or cardinality, a filled (mandatory) or empty (optional)
// circle on top, FODA's arcs under oneOf (hollow) and someOf (filled) groups, + and − to include
// and exclude, and collapsible subtrees (three dots under a collapsed feature). Decisions change
// colours and counts, never the layout; only expanding or collapsing lays the tree out again,
// keeping the clicked feature where it was on screen. It fits its panel on load and on resize
// (until you zoom or pan), and has fit / zoom buttons and keys (f, +, -).
import { hierarchy, tree as d3tree, HierarchyPointNode } from 'd3-hierarchy';
import { select, Selection } from 'd3-selection';
import 'd3-transition';
import { zoom as d3zoom, zoomIdentity, ZoomBehavior, ZoomTransform } from 'd3-zoom';
import { el, endEllipsis, formatCount, middleEllipsis, percent, textWidth } from './format';
import { FeatureIndex, FeatureStatus, FeatureView, FeatureViewHandlers, nextValue, STATUS_WORDS, statusOf } from './model';
import type { Counts, FeatureNode, State } from './types';

/** the box width: wider for a model whose names are long (automotive01: N_100300__F_100301) */
let W = 150;
const H = 56;
const GAP_X = 18;
const GAP_Y = 62;
const NAME_FONT = '600 13px system-ui, sans-serif';
const GROUP_FONT = 'italic 11px system-ui, sans-serif';
const COUNT_FONT = '11px system-ui, sans-serif';
/** features drawn on load beyond the first level (whole levels are added while they fit) */
const INITIAL_NODES = 40;
/** the smallest scale the first view is drawn at when more than the first level is expanded */
const READABLE = 0.62;
/** the smallest scale of the automatic fit: names about 6 px high (the fit button shows it all) */
const MIN_AUTO_SCALE = 0.45;
const SVGNS = 'http://www.w3.org/2000/svg';
// children drawn under an expanded feature before "••• N more" (a flat model of 2,500 features
// under its root stays fast to draw and to click); each click on it draws MORE_KIDS more
const MAX_KIDS = 40;
const MORE_KIDS = 100;
const ARC_R = 13;
const CONTROLS_W = 40;

interface ViewNode {
  key: string;
  data: FeatureNode;
  parentGroup: string | null; // the kind of the parent's group
  kids: ViewNode[];
  hidden: number; // children not shown (collapsed)
}

/** How small the diagram must be drawn for its first level to fit a panel of this width (the
 * page shows the tree instead when that is too small to read). */
export function firstLevelScale(index: FeatureIndex, width: number): number {
  const n = Math.min(index.root.children.length, MAX_KIDS);
  return width / Math.max(1, n * (boxWidth(index) + GAP_X) + 20);
}

export class Diagram implements FeatureView {
  readonly kind = 'diagram' as const;
  private svg: Selection<SVGSVGElement, unknown, null, undefined>;
  private layer: Selection<SVGGElement, unknown, null, undefined>;
  private linkLayer: Selection<SVGGElement, unknown, null, undefined>;
  private arcLayer: Selection<SVGGElement, unknown, null, undefined>;
  private nodeLayer: Selection<SVGGElement, unknown, null, undefined>;
  private zoom: ZoomBehavior<SVGSVGElement, unknown>;
  private expanded = new Set<string>();
  private byId: Map<string, FeatureNode>;
  private parentOf: Map<string, string>;
  private root: FeatureNode;
  private state: State | null = null;
  private counts: Counts | null = null;
  private positions = new Map<string, { x: number; y: number }>();
  private highlighted: string | null = null;
  private linked = new Set<string>();
  /** fit the panel on resize, until the user zooms or pans */
  private autoFit = true;
  private fitting = false;
  private kidLimit = new Map<string, number>(); // feature -> children drawn (default MAX_KIDS)
  private pinned = new Set<string>(); // features drawn whatever their parent's limit (found ones)
  private resize: ResizeObserver;
  private lastSize = '';
  private controls: HTMLElement;

  constructor(private host: HTMLElement, private index: FeatureIndex, private handlers: FeatureViewHandlers) {
    W = boxWidth(index);
    this.root = index.root;
    this.byId = index.byId;
    this.parentOf = index.parentOf;
    this.initialExpansion();
    this.svg = select(host).append('svg').attr('class', 'diagram').attr('role', 'tree').attr('tabindex', '0')
      .attr('aria-label', 'feature diagram (f: fit, +/-: zoom)') as unknown as Selection<SVGSVGElement, unknown, null, undefined>;
    this.layer = this.svg.append('g').attr('class', 'layer');
    this.linkLayer = this.layer.append('g').attr('class', 'links');
    this.arcLayer = this.layer.append('g').attr('class', 'arcs');
    this.nodeLayer = this.layer.append('g').attr('class', 'nodes');
    this.zoom = d3zoom<SVGSVGElement, unknown>()
      .scaleExtent([0.05, 3])
      .filter((ev: Event) => !(ev.target as Element).closest?.('.btn') && (ev.type !== 'mousedown' || !(ev as MouseEvent).button))
      .on('zoom', (ev: { transform: ZoomTransform; sourceEvent: Event | null }) => {
        this.layer.attr('transform', ev.transform.toString());
        if (ev.sourceEvent && !this.fitting) {
          this.autoFit = false; // the user zoomed or panned: keep their view on resize
        }
      });
    this.svg.call(this.zoom).on('dblclick.zoom', null);
    this.controls = zoomControls(host, () => this.fit(), (k) => this.zoomBy(k));
    this.svg.on('keydown', (ev: KeyboardEvent) => zoomKeys(ev, () => this.fit(), (k) => this.zoomBy(k)));
    this.render(null);
    this.resize = new ResizeObserver(() => {
      const b = this.host.getBoundingClientRect();
      const size = `${Math.round(b.width)}x${Math.round(b.height)}`;
      if (size !== this.lastSize && b.width && b.height) {
        this.lastSize = size;
        if (this.autoFit) {
          this.fit(false, true);
        }
      }
    });
    this.resize.observe(host);
  }

  /** The root and its first level, then whole levels while the diagram, fitted to the panel, stays
   * readable (drawn at READABLE or larger) and small. */
  private initialExpansion(): void {
    this.expanded.add(this.root.id);
    const box = this.host.getBoundingClientRect();
    const bw = box.width || 600;
    const bh = box.height || 400;
    let shown = 1 + Math.min(this.root.children.length, MAX_KIDS);
    let frontier = this.root.children.slice(0, MAX_KIDS).filter((c) => !c.ref && c.children.length);
    while (frontier.length) {
      const more = frontier.reduce((n, c) => n + Math.min(c.children.length, MAX_KIDS), 0);
      if (shown + more > INITIAL_NODES) {
        return;
      }
      frontier.forEach((c) => this.expanded.add(c.id));
      const e = this.extent();
      if (Math.min((bw - CONTROLS_W) / e.w, bh / e.h) < READABLE) {
        frontier.forEach((c) => this.expanded.delete(c.id));
        return;
      }
      shown += more;
      frontier = frontier.flatMap((c) => c.children.slice(0, MAX_KIDS).filter((k) => !k.ref && k.children.length));
    }
  }

  /** The size of the diagram as it would be drawn now (layout units). */
  private extent(): { w: number; h: number } {
    const laid = d3tree<ViewNode>().nodeSize([W + GAP_X, H + GAP_Y])(hierarchy<ViewNode>(this.view(), (d) => d.kids));
    const ns = laid.descendants();
    const xs = ns.map((n) => n.x);
    const ys = ns.map((n) => n.y);
    return { w: Math.max(...xs) - Math.min(...xs) + W + 24, h: Math.max(...ys) - Math.min(...ys) + H + 46 };
  }

  private view(): ViewNode {
    const build = (n: FeatureNode, key: string, parentGroup: string | null): ViewNode => {
      const open = this.expanded.has(n.id) && !n.ref;
      const limit = this.kidLimit.get(n.id) ?? MAX_KIDS;
      const kids: ViewNode[] = [];
      if (open) {
        n.children.forEach((c, i) => {
          if (i < limit || this.pinned.has(c.id)) {
            kids.push(build(c, `${key}/${i}:${c.id}`, n.group?.kind ?? null));
          }
        });
      }
      return {
        key,
        data: n,
        parentGroup,
        kids,
        hidden: n.ref ? 0 : n.children.length - kids.length,
      };
    };
    return build(this.root, this.root.id, null);
  }

  status(id: string): FeatureStatus {
    return statusOf(this.state, id);
  }

  /** Lay out and draw; `anchor`: a feature to keep at the same place on screen. */
  private render(anchor: string | null): void {
    const rootView = hierarchy<ViewNode>(this.view(), (d) => d.kids);
    const laid = d3tree<ViewNode>().nodeSize([W + GAP_X, H + GAP_Y])(rootView);
    const nodes = laid.descendants();
    const t = this.currentTransform();
    let before: { x: number; y: number } | undefined;
    if (anchor) {
      before = this.positions.get(anchor);
    }
    this.positions.clear();
    nodes.forEach((n) => this.positions.set(n.data.key, { x: n.x, y: n.y }));

    const links = this.linkLayer.selectAll<SVGPathElement, HierarchyPointNode<ViewNode>>('path.link')
      .data(nodes.filter((n) => n.parent), (d) => d.data.key);
    links.exit().remove();
    links.enter().append('path').attr('class', 'link')
      .merge(links)
      .attr('d', (d) => {
        const p = d.parent as HierarchyPointNode<ViewNode>;
        const y1 = p.y + H / 2;
        const y2 = d.y - H / 2 - 6;
        return `M${p.x},${y1} L${d.x},${y2}`; // straight, as FODA draws them (the group arcs sit on them)
      });

    // FODA's group arcs under a parent, across the lines to its children: hollow for oneOf
    // (alternative) and cardinality groups, filled between the outermost lines for someOf (or)
    const grouped = nodes.filter((n) => (n.children?.length ?? 0) >= 2 &&
      ['oneOf', 'someOf', 'card'].includes(n.data.data.group?.kind ?? ''));
    const arcs = this.arcLayer.selectAll<SVGPathElement, HierarchyPointNode<ViewNode>>('path.arc')
      .data(grouped, (d) => d.data.key);
    arcs.exit().remove();
    arcs.enter().append('path').merge(arcs)
      .attr('class', (d) => `arc ${d.data.data.group?.kind}`)
      .attr('d', (d) => {
        const px = d.x;
        const py = d.y + H / 2;
        const angles = (d.children ?? []).map((c) => Math.atan2(c.y - H / 2 - 6 - py, c.x - px));
        const a0 = Math.min(...angles);
        const a1 = Math.max(...angles);
        const p0 = `${(px + ARC_R * Math.cos(a0)).toFixed(1)},${(py + ARC_R * Math.sin(a0)).toFixed(1)}`;
        const p1 = `${(px + ARC_R * Math.cos(a1)).toFixed(1)},${(py + ARC_R * Math.sin(a1)).toFixed(1)}`;
        return d.data.data.group?.kind === 'someOf'
          ? `M${px},${py} L${p0} A${ARC_R},${ARC_R} 0 0 1 ${p1} Z`
          : `M${p0} A${ARC_R},${ARC_R} 0 0 1 ${p1}`;
      });

    const sel = this.nodeLayer.selectAll<SVGGElement, HierarchyPointNode<ViewNode>>('g.feature')
      .data(nodes, (d) => d.data.key);
    sel.exit().remove();
    const enter = sel.enter().append('g').attr('class', 'feature');
    enter.each((d, i, groups) => this.buildNode(select(groups[i]), d.data));
    enter.merge(sel).attr('transform', (d) => `translate(${d.x},${d.y})`)
      .each((d, i, groups) => {
        const more = d.data.hidden ? `••• ${d.data.hidden}${d.data.kids.length ? ' more' : ''}` : '';
        select(groups[i]).select('text.more').text(more)
          .attr('data-more', d.data.kids.length && d.data.hidden ? 'partial' : null);
      });

    if (this.autoFit) {
      // the user has not zoomed or panned: what is drawn is fitted to the panel again
      this.fit(anchor !== null, true, anchor);
    } else if (anchor && before) {
      const after = this.positions.get(anchor);
      if (after) {
        this.fitting = true;
        this.svg.call(this.zoom.transform, t.translate(before.x - after.x, before.y - after.y));
        this.fitting = false;
      }
    }
    this.restyle();
    this.handlers.shown();
  }

  private currentTransform(): ZoomTransform {
    const node = this.svg.node() as SVGSVGElement & { __zoom?: ZoomTransform };
    return node.__zoom ?? zoomIdentity;
  }

  /** Fit the whole drawn diagram in the panel (never larger than 1.2). The automatic fit (on load,
   * on resize) stops at a readable scale: a first level too wide for the panel is then shown from
   * its root, and the fit button or key shows all of it. */
  fit(animate = true, readable = false, anchor: string | null = null): void {
    const box = this.host.getBoundingClientRect();
    if (!box.width || !box.height || !this.positions.size) {
      return;
    }
    const ps = [...this.positions.values()];
    const minX = Math.min(...ps.map((p) => p.x)) - W / 2 - 12;
    const maxX = Math.max(...ps.map((p) => p.x)) + W / 2 + 12;
    const minY = Math.min(...ps.map((p) => p.y)) - H / 2 - 20;
    const maxY = Math.max(...ps.map((p) => p.y)) + H / 2 + 26;
    const bw = box.width - CONTROLS_W; // the zoom buttons keep the right edge
    let k = Math.min(1.2, bw / (maxX - minX), box.height / (maxY - minY));
    let tx = bw / 2 - k * (minX + maxX) / 2;
    if (readable && k < MIN_AUTO_SCALE) {
      // too wide to read whole. After an unfold: readable, centred on what was unfolded (the fit
      // button shows all of it). Otherwise (on load, on resize): readable, but never so small
      // that the first level does not fit, nor so large that it is cut
      const keyOf = (pred: (key: string) => boolean) => [...this.positions.entries()].filter(([key]) => pred(key)).map(([, p]) => p.x);
      const top = keyOf((key) => key.split('/').length <= 2);
      const fMin = Math.min(...top) - W / 2 - 12;
      const fMax = Math.max(...top) + W / 2 + 12;
      if (anchor && this.positions.has(anchor)) {
        k = MIN_AUTO_SCALE;
        const sub = keyOf((key) => key === anchor || key.startsWith(anchor + '/'));
        const sMin = Math.min(...sub) - W / 2 - 12;
        const sMax = Math.max(...sub) + W / 2 + 12;
        tx = bw / 2 - k * (sMin + sMax) / 2;
        if (k * (sMax - sMin) > bw) {
          tx = bw / 2 - k * (this.positions.get(anchor)?.x ?? 0);
        }
      } else {
        k = Math.max(k, Math.min(MIN_AUTO_SCALE, bw / (fMax - fMin)));
        const at = this.positions.get(this.root.id);
        tx = bw / 2 - k * (at?.x ?? 0);
        if (k * (fMax - fMin) <= bw) {
          tx = Math.min(-k * fMin, Math.max(bw - k * fMax, tx));
        }
      }
    }
    const ty = 8 - k * minY; // top-aligned, as a tree reads
    this.autoFit = true;
    this.fitting = true;
    const to = zoomIdentity.translate(tx, ty).scale(k);
    if (animate) {
      this.svg.transition().duration(250).call(this.zoom.transform, to).on('end', () => { this.fitting = false; });
    } else {
      this.svg.call(this.zoom.transform, to);
      this.fitting = false;
    }
  }

  /** Zoom around the selected feature when it is on screen, else around the middle of the top of
   * the drawing (the tree hangs from there). */
  zoomBy(factor: number): void {
    this.autoFit = false;
    const box = this.host.getBoundingClientRect();
    const t = this.currentTransform();
    let p: [number, number] = [(box.width - CONTROLS_W) / 2, Math.min(box.height / 2, 120)];
    let sel: { x: number; y: number } | undefined;
    this.nodeLayer.selectAll<SVGGElement, HierarchyPointNode<ViewNode>>('g.feature').each((d) => {
      if (d.data.data.id === this.highlighted && !sel) sel = this.positions.get(d.data.key);
    });
    if (sel) {
      const sx = t.applyX(sel.x);
      const sy = t.applyY(sel.y);
      if (sx >= 0 && sx <= box.width && sy >= 0 && sy <= box.height) p = [sx, sy];
    }
    this.svg.transition().duration(150).call(this.zoom.scaleBy, factor, p);
  }

  private buildNode(g: Selection<SVGGElement, unknown, null, undefined>, v: ViewNode): void {
    const f = v.data;
    g.attr('data-feature', f.id).attr('role', 'treeitem').attr('aria-label', f.name);
    const title = document.createElementNS(SVGNS, 'title');
    title.textContent = f.longName + (f.ref ? ' (shared: declared elsewhere)' : '');
    g.node()?.appendChild(title);
    // the circle on top: filled mandatory / empty optional under an allOf (and/[n..n]) parent; in
    // oneOf / someOf / [i..j] groups the group decides, and only an explicit `opt` is marked
    const marked = v.parentGroup !== null && (f.kind === 'mandatory' || f.kind === 'optional' ||
      (f.kind === undefined && (v.parentGroup === 'allOf' || f.optional)));
    if (marked) {
      g.append('circle').attr('class', f.optional ? 'mark optional' : 'mark mandatory')
        .attr('cx', 0).attr('cy', -H / 2 - 6).attr('r', 5.5)
        .append('title').text(f.optional ? 'optional' : 'mandatory');
    }
    const box = g.append('rect').attr('class', 'box' + (f.ref ? ' ref' : ''))
      .attr('x', -W / 2).attr('y', -H / 2).attr('width', W).attr('height', H).attr('rx', 6);
    const textX = -W / 2 + 8;
    g.append('text').attr('class', 'name').attr('x', textX).attr('y', -H / 2 + 18)
      .text(middleEllipsis(f.name, W - 44, NAME_FONT));
    g.append('text').attr('class', 'group').attr('x', textX).attr('y', -H / 2 + 33)
      .text(endEllipsis(f.group ? f.group.text : f.ref ? 'shared' : '', W - 44, GROUP_FONT));
    g.append('text').attr('class', 'count').attr('x', textX).attr('y', -H / 2 + 48).text('');
    const hasKids = f.children.length > 0 && !f.ref;
    if (hasKids) {
      box.style('cursor', 'pointer');
      box.on('click', () => this.toggle(f.id, v.key));
      g.select('text.name').style('cursor', 'pointer').on('click', () => this.toggle(f.id, v.key));
      g.append('text').attr('class', 'more').attr('x', 0).attr('y', H / 2 + 14).attr('text-anchor', 'middle')
        .text(v.hidden ? `••• ${v.hidden}` : '')
        .on('click', () => this.more(f.id, v.key));
    } else {
      box.on('click', () => {
        this.highlighted = f.id;
        this.restyle();
        this.handlers.select(f);
      });
    }
    if (!f.ref) {
      this.button(g, 'include', '+', W / 2 - 14, -H / 2 + 14, f);
      this.button(g, 'exclude', '−', W / 2 - 14, H / 2 - 14, f);
    }
  }

  private button(g: Selection<SVGGElement, unknown, null, undefined>, kind: 'include' | 'exclude', glyph: string,
    x: number, y: number, f: FeatureNode): void {
    const b = g.append('g').attr('class', `btn btn-${kind}`).attr('transform', `translate(${x},${y})`)
      .attr('role', 'button').attr('tabindex', '0');
    b.append('circle').attr('r', 9.5);
    b.append('text').attr('text-anchor', 'middle').attr('dy', '0.35em').text(glyph);
    b.append('title');
    const act = (ev: Event) => {
      ev.stopPropagation();
      this.highlighted = f.id;
      this.handlers.select(f);
      // clicking your own decision again undoes it
      this.handlers.decide(f.id, nextValue(this.status(f.id), kind === 'include'));
    };
    b.on('click', act).on('keydown', (ev: KeyboardEvent) => {
      if (ev.key === 'Enter' || ev.key === ' ') {
        act(ev);
      }
    });
  }

  /** "••• N": expand a collapsed feature; under an expanded one, draw more of its children. */
  private more(id: string, key: string): void {
    const f = this.byId.get(id);
    if (f && this.expanded.has(id)) {
      const limit = this.kidLimit.get(id) ?? MAX_KIDS;
      if (limit < f.children.length) {
        this.kidLimit.set(id, limit + MORE_KIDS);
        this.render(key);
        return;
      }
    }
    this.toggle(id, key);
  }

  private toggle(id: string, key: string): void {
    if (this.expanded.has(id)) {
      this.expanded.delete(id);
    } else {
      this.expanded.add(id);
    }
    const f = this.byId.get(id);
    if (f) {
      this.highlighted = id;
      this.handlers.select(f);
    }
    this.render(key);
  }

  setState(state: State): void {
    this.state = state;
    this.restyle();
  }

  setCounts(counts: Counts | null): void {
    this.counts = counts;
    this.restyle();
  }

  private restyle(): void {
    const counts = this.counts;
    this.nodeLayer.selectAll<SVGGElement, HierarchyPointNode<ViewNode>>('g.feature').each((d, i, groups) => {
      const g = select(groups[i]);
      const f = d.data.data;
      const st = this.status(f.id);
      g.attr('class', `feature st-${st}${this.highlighted === f.id && !f.ref ? ' highlight' : ''}${this.linked.has(f.id) ? ' linked' : ''}`)
        .attr('data-status', st);
      const n = counts?.features[f.id];
      const rem = counts?.remaining ?? null;
      g.select('text.count').text(n !== undefined && rem !== null
        ? endEllipsis(`in ${formatCount(n)} (${percent(n, rem)})`, W - 36, COUNT_FONT) : counts ? '…' : '');
      g.select('title').text(`${f.longName}: ${STATUS_WORDS[st]}` + (f.kindText ? `\n${f.kindText}` : '') +
        (n !== undefined && rem !== null ? `\nin ${formatCount(n)} of ${formatCount(rem)} remaining products` : ''));
      g.select('.btn-include title').text(st === 'user-in' ? `Undo: include ${f.name}` : `Include ${f.name}`);
      g.select('.btn-exclude title').text(st === 'user-out' ? `Undo: exclude ${f.name}` : `Exclude ${f.name}`);
      g.select('.btn-include').classed('active', st === 'user-in' || st === 'implied-in');
      g.select('.btn-exclude').classed('active', st === 'user-out' || st === 'implied-out');
    });
  }

  /** Features currently drawn (the counts are asked for these first). */
  visibleIds(): string[] {
    const out: string[] = [];
    this.nodeLayer.selectAll<SVGGElement, HierarchyPointNode<ViewNode>>('g.feature').each((d) => {
      if (!d.data.data.ref) {
        out.push(d.data.data.id);
      }
    });
    return out;
  }

  /** Expand the ancestors of a feature, bring it into view and highlight it. */
  reveal(id: string): void {
    let c = id;
    let p = this.parentOf.get(id);
    while (p) {
      this.expanded.add(p);
      this.pinned.add(c); // drawn even beyond its parent's first children
      c = p;
      p = this.parentOf.get(p);
    }
    this.highlighted = id;
    this.render(null);
    let key: string | undefined;
    this.nodeLayer.selectAll<SVGGElement, HierarchyPointNode<ViewNode>>('g.feature').each((d) => {
      if (d.data.data.id === id && !d.data.data.ref && key === undefined) {
        key = d.data.key;
      }
    });
    const pos = key ? this.positions.get(key) : undefined;
    if (!pos) {
      return;
    }
    const box = this.host.getBoundingClientRect();
    const t = this.currentTransform();
    const sx = t.applyX(pos.x);
    const sy = t.applyY(pos.y);
    const inside = sx - (W / 2) * t.k >= 0 && sx + (W / 2) * t.k <= box.width && sy - (H / 2) * t.k >= 0 &&
      sy + (H / 2) * t.k <= box.height;
    if (inside && t.k >= 0.5) {
      return;
    }
    const k = Math.max(t.k, 0.8);
    this.autoFit = false;
    this.fitting = true;
    this.svg.transition().duration(300)
      .call(this.zoom.transform, zoomIdentity.translate(box.width / 2 - k * pos.x, box.height / 2 - k * pos.y).scale(k))
      .on('end', () => { this.fitting = false; });
  }

  select(id: string | null): void {
    this.highlighted = id;
    this.restyle();
  }

  setLinked(ids: Set<string>): void {
    this.linked = ids;
    this.restyle();
  }

  expandAll(limit = 400): void {
    const order: FeatureNode[] = [this.root];
    let shown = 1;
    while (order.length) {
      const n = order.shift() as FeatureNode;
      if (n.ref || !n.children.length) {
        continue;
      }
      const k = Math.min(n.children.length, this.kidLimit.get(n.id) ?? MAX_KIDS);
      if (shown + k > limit) {
        break;
      }
      this.expanded.add(n.id);
      shown += k;
      order.push(...n.children.slice(0, k));
    }
    this.autoFit = true;
    this.render(null);
  }

  collapseAll(): void {
    this.expanded.clear();
    this.kidLimit.clear();
    this.pinned.clear();
    this.expanded.add(this.root.id);
    this.autoFit = true;
    this.render(null);
  }

  focus(): void {
    (this.svg.node() as SVGSVGElement).focus({ preventScroll: true });
  }

  destroy(): void {
    this.resize.disconnect();
    this.controls.remove();
    this.svg.remove();
  }

  /** The current zoom scale (tests). */
  get scale(): number {
    return this.currentTransform().k;
  }
}

/** A box wide enough for most of the model's names (the 90th percentile, 150 to 220 px). */
function boxWidth(index: FeatureIndex): number {
  const names = index.order.slice(0, 3000).map((f) => f.name);
  if (!names.length) {
    return 150;
  }
  const ws = names.map((n) => textWidth(n, NAME_FONT)).sort((a, b) => a - b);
  const p90 = ws[Math.min(ws.length - 1, Math.floor(ws.length * 0.9))];
  return Math.round(Math.max(150, Math.min(220, p90 + 46)));
}

/** Fit / zoom in / zoom out buttons in a corner of a panel. */
export function zoomControls(host: HTMLElement, fit: () => void, zoom: (k: number) => void): HTMLElement {
  const b = (cls: string, label: string, title: string, fn: () => void) => {
    const x = el('button', { class: `zoom-btn ${cls}`, title, 'aria-label': title }, label);
    x.addEventListener('click', (ev) => {
      ev.stopPropagation();
      fn();
    });
    return x;
  };
  const box = el('div', { class: 'zoom-controls' },
    b('fit', '⤢', 'Fit to the panel (f)', fit), b('zoom-in', '+', 'Zoom in (+)', () => zoom(1.3)),
    b('zoom-out', '−', 'Zoom out (-)', () => zoom(1 / 1.3)));
  host.append(box);
  return box;
}

/** f / 0: fit; + / =: zoom in; -: zoom out. */
export function zoomKeys(ev: KeyboardEvent, fit: () => void, zoom: (k: number) => void): void {
  if (ev.ctrlKey || ev.metaKey || ev.altKey) {
    return;
  }
  if (ev.key === 'f' || ev.key === '0') {
    fit();
  } else if (ev.key === '+' || ev.key === '=') {
    zoom(1.3);
  } else if (ev.key === '-' || ev.key === '_') {
    zoom(1 / 1.3);
  } else {
    return;
  }
  ev.preventDefault();
}
