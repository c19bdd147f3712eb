// The feature diagram, drawn as the thesis drew it (Figures 17 and 19): a top-down tree of
// rectangles with the group kind or cardinality, a filled (mandatory) or empty (optional)
// circle on top, + and − to include and exclude, and collapsible subtrees (three dots under a
// collapsed feature). Decisions change colours and counts, never the layout; only expanding or
// collapsing lays the tree out again, keeping the clicked feature where it was on screen.
import { hierarchy, tree as d3tree, HierarchyPointNode } from 'd3-hierarchy';
import { select, Selection } from 'd3-selection';
import 'd3-transition';
import { zoom as d3zoom, zoomIdentity, ZoomBehavior, ZoomTransform } from 'd3-zoom';
import { formatCount, percent } from './format';
import type { Counts, FeatureNode, State } from './types';

const W = 164;
const H = 60;
const GAP_X = 22;
const GAP_Y = 64;
const SVGNS = 'http://www.w3.org/2000/svg';
// children drawn under an expanded feature before "••• N more" (a flat model of 2,500 features
// under its root stays fast to draw and to click); each click on it draws MORE_KIDS more
const MAX_KIDS = 40;
/** The smallest scale the diagram is fitted at: feature names stay about 8 px high or more. */
const MIN_FIT_SCALE = 0.65;
const MORE_KIDS = 100;

interface ViewNode {
  key: string;
  data: FeatureNode;
  parentGroup: string | null; // the kind of the parent's group
  kids: ViewNode[];
  hidden: number; // children not shown (collapsed)
}

export interface DiagramHandlers {
  decide(feature: string, value: boolean | null): void;
  select(feature: FeatureNode): void;
}

export type FeatureStatus = 'user-in' | 'user-out' | 'implied-in' | 'implied-out' | 'open';

export class Diagram {
  private svg: Selection<SVGSVGElement, unknown, null, undefined>;
  private layer: Selection<SVGGElement, unknown, null, undefined>;
  private linkLayer: Selection<SVGGElement, unknown, null, undefined>;
  private arcLayer: Selection<SVGGElement, unknown, null, undefined>;
  private nodeLayer: Selection<SVGGElement, unknown, null, undefined>;
  private zoom: ZoomBehavior<SVGSVGElement, unknown>;
  private expanded = new Set<string>();
  private byId = new Map<string, FeatureNode>();
  private parentOf = new Map<string, string>();
  private state: State | null = null;
  private counts: Counts | null = null;
  private positions = new Map<string, { x: number; y: number }>();
  private highlighted: string | null = null;
  private fitted = false;
  private kidLimit = new Map<string, number>(); // feature -> children drawn (default MAX_KIDS)
  private pinned = new Set<string>(); // features drawn whatever their parent's limit (found ones)

  constructor(private host: HTMLElement, private root: FeatureNode, private handlers: DiagramHandlers) {
    const index = (n: FeatureNode, parent?: FeatureNode) => {
      if (!n.ref) {
        this.byId.set(n.id, n);
        if (parent) {
          this.parentOf.set(n.id, parent.id);
        }
        n.children.forEach((c) => index(c, n));
      }
    };
    index(root);
    this.initialExpansion();
    this.svg = select(host).append('svg').attr('class', 'diagram').attr('role', 'tree')
      .attr('aria-label', 'feature diagram') as unknown as Selection<SVGSVGElement, unknown, null, undefined>;
    this.layer = this.svg.append('g').attr('class', 'layer');
    this.linkLayer = this.layer.append('g').attr('class', 'links');
    this.arcLayer = this.layer.append('g').attr('class', 'arcs');
    this.nodeLayer = this.layer.append('g').attr('class', 'nodes');
    this.zoom = d3zoom<SVGSVGElement, unknown>()
      .scaleExtent([0.1, 2.5])
      .filter((ev: Event) => !(ev.target as Element).closest?.('.btn'))
      .on('zoom', (ev: { transform: ZoomTransform }) => this.layer.attr('transform', ev.transform.toString()));
    this.svg.call(this.zoom).on('dblclick.zoom', null);
    this.render(null);
  }

  /** Expand breadth-first until about 40 features show (a 2,000-feature model stays usable). */
  private initialExpansion(): void {
    let shown = 1;
    let frontier = [this.root];
    while (frontier.length) {
      const next: FeatureNode[] = [];
      for (const n of frontier) {
        if (!n.children.length || n.ref) {
          continue;
        }
        if (shown + n.children.length > 40 && shown > 1) {
          return;
        }
        this.expanded.add(n.id);
        shown += Math.min(n.children.length, MAX_KIDS);
        next.push(...n.children.slice(0, MAX_KIDS));
      }
      frontier = next;
    }
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
    const s = this.state;
    if (!s) {
      return 'open';
    }
    if (id in s.decisions) {
      return s.decisions[id] ? 'user-in' : 'user-out';
    }
    if (id in s.implied) {
      return s.implied[id] ? 'implied-in' : 'implied-out';
    }
    return 'open';
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

    // FODA's group arcs under a parent: hollow for oneOf (alternative), filled for someOf (or)
    const grouped = nodes.filter((n) => (n.children?.length ?? 0) >= 2 &&
      (n.data.data.group?.kind === 'oneOf' || n.data.data.group?.kind === 'someOf'));
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
        const r = 22;
        const p0 = `${px + r * Math.cos(a0)},${py + r * Math.sin(a0)}`;
        const p1 = `${px + r * Math.cos(a1)},${py + r * Math.sin(a1)}`;
        return d.data.data.group?.kind === 'someOf'
          ? `M${px},${py} L${p0} A${r},${r} 0 0 1 ${p1} Z`
          : `M${p0} A${r},${r} 0 0 1 ${p1}`;
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

    if (anchor && before) {
      const after = this.positions.get(anchor);
      if (after) {
        const nt = t.translate(before.x - after.x, before.y - after.y);
        this.svg.call(this.zoom.transform, nt);
      }
    } else if (!this.fitted) {
      this.fit(nodes);
    }
    this.restyle();
  }

  private currentTransform(): ZoomTransform {
    const node = this.svg.node() as SVGSVGElement & { __zoom?: ZoomTransform };
    return node.__zoom ?? zoomIdentity;
  }

  private fit(nodes: HierarchyPointNode<ViewNode>[]): void {
    const box = this.host.getBoundingClientRect();
    if (!box.width || !box.height) {
      return;
    }
    const xs = nodes.map((n) => n.x);
    const ys = nodes.map((n) => n.y);
    const minX = Math.min(...xs) - W / 2 - 10;
    const maxX = Math.max(...xs) + W / 2 + 10;
    const minY = Math.min(...ys) - H / 2 - 20;
    const maxY = Math.max(...ys) + H / 2 + 24;
    // never smaller than readable: a tree wider than the panel is shown from its root, and the
    // user drags to see the rest (fitting 11 leaves into a half-screen panel drew 4 px text)
    const k = Math.max(MIN_FIT_SCALE, Math.min(1.2, box.width / (maxX - minX), box.height / (maxY - minY)));
    const rootX = nodes.length ? nodes[0].x : 0;
    const tx = k * (maxX - minX) <= box.width ? box.width / 2 - k * (minX + maxX) / 2
      : Math.min(-k * minX, Math.max(box.width - k * maxX, box.width / 2 - k * rootX));
    const ty = 16 - k * minY;
    this.svg.call(this.zoom.transform, zoomIdentity.translate(tx, ty).scale(k));
    this.fitted = true;
  }

  private buildNode(g: Selection<SVGGElement, unknown, null, undefined>, v: ViewNode): void {
    const f = v.data;
    g.attr('data-feature', f.id).attr('role', 'treeitem').attr('aria-label', f.name);
    const title = document.createElementNS(SVGNS, 'title');
    title.textContent = f.longName + (f.ref ? ' (shared: declared elsewhere)' : '');
    g.node()?.appendChild(title);
    // the circle on top: filled mandatory / empty optional under an allOf (and/[n..n]) parent; in
    // oneOf / someOf / [i..j] groups the group decides, and only an explicit `opt` is marked
    const marked = v.parentGroup !== null && (v.parentGroup === 'allOf' || f.optional);
    if (marked) {
      g.append('circle').attr('class', f.optional ? 'mark optional' : 'mark mandatory')
        .attr('cx', 0).attr('cy', -H / 2 - 6).attr('r', 5.5)
        .append('title').text(f.optional ? 'optional' : 'mandatory');
    }
    const box = g.append('rect').attr('class', 'box' + (f.ref ? ' ref' : ''))
      .attr('x', -W / 2).attr('y', -H / 2).attr('width', W).attr('height', H).attr('rx', 6);
    const textX = -W / 2 + 10;
    g.append('text').attr('class', 'name').attr('x', textX).attr('y', -H / 2 + 18).text(clip(f.name, 17));
    g.append('text').attr('class', 'group').attr('x', textX).attr('y', -H / 2 + 34)
      .text(f.group ? f.group.text : f.ref ? 'shared' : '');
    g.append('text').attr('class', 'count').attr('x', textX).attr('y', -H / 2 + 50).text('');
    const hasKids = f.children.length > 0 && !f.ref;
    if (hasKids) {
      box.style('cursor', 'pointer');
      box.on('click', () => this.toggle(f.id, v.key));
      g.select('text.name').style('cursor', 'pointer').on('click', () => this.toggle(f.id, v.key));
      g.append('text').attr('class', 'more').attr('x', 0).attr('y', H / 2 + 14).attr('text-anchor', 'middle')
        .text(v.hidden ? `••• ${v.hidden}` : '')
        .on('click', () => this.more(f.id, v.key));
    } else {
      box.on('click', () => this.handlers.select(f));
    }
    this.button(g, 'include', '+', W / 2 - 16, -H / 2 + 16, f);
    this.button(g, 'exclude', '−', W / 2 - 16, H / 2 - 16, f);
  }

  private button(g: Selection<SVGGElement, unknown, null, undefined>, kind: 'include' | 'exclude', glyph: string,
    x: number, y: number, f: FeatureNode): void {
    const b = g.append('g').attr('class', `btn btn-${kind}`).attr('transform', `translate(${x},${y})`)
      .attr('role', 'button').attr('tabindex', '0');
    b.append('circle').attr('r', 10);
    b.append('text').attr('text-anchor', 'middle').attr('dy', '0.35em').text(glyph);
    b.append('title');
    const act = (ev: Event) => {
      ev.stopPropagation();
      const st = this.status(f.id);
      const want = kind === 'include';
      // clicking your own decision again undoes it
      if ((st === 'user-in' && want) || (st === 'user-out' && !want)) {
        this.handlers.decide(f.id, null);
      } else {
        this.handlers.decide(f.id, want);
      }
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
    this.render(key);
    const f = this.byId.get(id);
    if (f) {
      this.handlers.select(f);
    }
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
      g.attr('class', `feature st-${st}${this.highlighted === f.id ? ' highlight' : ''}`).attr('data-status', st);
      const n = counts?.features[f.id];
      const rem = counts?.remaining ?? null;
      g.select('text.count').text(n !== undefined && rem !== null ? `in ${formatCount(n)} (${percent(n, rem)})` : counts ? '…' : '');
      const words: Record<FeatureStatus, string> = {
        'user-in': 'included (your decision)',
        'user-out': 'excluded (your decision)',
        'implied-in': 'included (implied)',
        'implied-out': 'excluded (implied)',
        open: 'open',
      };
      g.select('title').text(`${f.longName}: ${words[st]}` + (n !== undefined && rem !== null ? `\nin ${n} of ${rem} remaining products` : ''));
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

  allIds(): string[] {
    return [...this.byId.keys()];
  }

  find(query: string, limit = 20): FeatureNode[] {
    const q = query.trim().toLowerCase();
    if (!q) {
      return [];
    }
    const starts: FeatureNode[] = [];
    const contains: FeatureNode[] = [];
    for (const f of this.byId.values()) {
      const n = f.name.toLowerCase();
      if (n.startsWith(q)) {
        starts.push(f);
      } else if (f.longName.toLowerCase().includes(q)) {
        contains.push(f);
      }
      if (starts.length >= limit) {
        break;
      }
    }
    return [...starts, ...contains].slice(0, limit);
  }

  /** Expand the ancestors of a feature, centre on it and highlight it. */
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
    if (pos) {
      const box = this.host.getBoundingClientRect();
      const k = Math.max(this.currentTransform().k, 0.8);
      this.svg.transition().duration(300)
        .call(this.zoom.transform, zoomIdentity.translate(box.width / 2 - k * pos.x, box.height / 2 - k * pos.y).scale(k));
    }
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
    this.fitted = false;
    this.render(null);
  }

  collapseAll(): void {
    this.expanded.clear();
    this.kidLimit.clear();
    this.pinned.clear();
    this.expanded.add(this.root.id);
    this.fitted = false;
    this.render(null);
  }

  refit(): void {
    this.fitted = false;
    this.render(null);
  }
}

function clip(s: string, n: number): string {
  return s.length <= n ? s : s.slice(0, n - 1) + '…';
}
