// The indented tree of features, as FeatureIDE's and uvl-lsp's configuration editors show big
// models: one row per feature (a checkbox to include, a cross to exclude, the kind, the count),
// expand / collapse, keyboard navigation (arrows, Home / End, PageUp / PageDown, Space / + to
// include, - / x to exclude, Backspace to undo your decision), and virtualised: only the rows on
// screen exist in the page, so Linux's 6,467 features scroll as smoothly as 10.
import { el, formatCount, middleEllipsis, percent } from './format';
import { FeatureIndex, FeatureStatus, FeatureView, FeatureViewHandlers, nextValue, STATUS_WORDS, statusOf } from './model';
import type { Counts, FeatureNode, State } from './types';

export const ROW_H = 26;
const OVERSCAN = 8;
const INDENT = 16;
/** rows shown on load: the first level always, then whole levels while they fit this many */
const INITIAL_ROWS = 36;

interface Row {
  f: FeatureNode;
  depth: number;
}

export class TreeView implements FeatureView {
  readonly kind = 'tree' as const;
  private scroller: HTMLElement;
  private spacer: HTMLElement;
  private layer: HTMLElement;
  private expanded = new Set<string>();
  private rows: Row[] = [];
  private rowIndex = new Map<string, number>();
  private cursor = 0;
  private selected: string | null = null;
  private linked = new Set<string>();
  private state: State | null = null;
  private counts: Counts | null = null;
  private frame = 0;
  private lastShown = '';
  private resize: ResizeObserver;

  constructor(private host: HTMLElement, private index: FeatureIndex, private handlers: FeatureViewHandlers) {
    this.scroller = el('div', {
      class: 'tree', role: 'tree', tabindex: '0', 'aria-label': 'features (arrows to move, space to include, x to exclude)',
    });
    this.spacer = el('div', { class: 'tree-spacer' });
    this.layer = el('div', { class: 'tree-rows' });
    this.spacer.append(this.layer);
    this.scroller.append(this.spacer);
    host.append(this.scroller);
    this.initialExpansion();
    this.flatten();
    this.scroller.addEventListener('scroll', () => this.schedule());
    this.scroller.addEventListener('keydown', (ev) => this.key(ev));
    this.scroller.addEventListener('click', (ev) => this.click(ev));
    this.resize = new ResizeObserver(() => this.schedule());
    this.resize.observe(this.scroller);
    this.render();
  }

  private initialExpansion(): void {
    const root = this.index.root;
    this.expanded.add(root.id);
    let shown = 1 + root.children.length;
    let frontier = root.children.filter((c) => !c.ref && c.children.length);
    while (frontier.length) {
      const more = frontier.reduce((n, c) => n + c.children.length, 0);
      if (shown + more > INITIAL_ROWS) {
        return;
      }
      frontier.forEach((c) => this.expanded.add(c.id));
      shown += more;
      frontier = frontier.flatMap((c) => c.children.filter((k) => !k.ref && k.children.length));
    }
  }

  private flatten(): void {
    const out: Row[] = [];
    const walk = (f: FeatureNode, depth: number) => {
      out.push({ f, depth });
      if (!f.ref && this.expanded.has(f.id)) {
        for (const c of f.children) {
          walk(c, depth + 1);
        }
      }
    };
    walk(this.index.root, 0);
    this.rows = out;
    this.rowIndex.clear();
    out.forEach((r, i) => {
      if (!r.f.ref && !this.rowIndex.has(r.f.id)) {
        this.rowIndex.set(r.f.id, i);
      }
    });
    this.spacer.style.height = `${out.length * ROW_H}px`;
    this.cursor = Math.min(this.cursor, out.length - 1);
  }

  private schedule(): void {
    if (!this.frame) {
      this.frame = requestAnimationFrame(() => {
        this.frame = 0;
        this.render();
      });
    }
  }

  private range(): [number, number] {
    const top = this.scroller.scrollTop;
    const h = this.scroller.clientHeight || 600;
    const first = Math.max(0, Math.floor(top / ROW_H) - OVERSCAN);
    const last = Math.min(this.rows.length, Math.ceil((top + h) / ROW_H) + OVERSCAN);
    return [first, last];
  }

  private render(): void {
    const [first, last] = this.range();
    this.layer.style.transform = `translateY(${first * ROW_H}px)`;
    // rows are kept and patched in place: a click that straddles a redraw (a count arriving
    // between mousedown and mouseup) still lands on the same element
    const keep = new Map<number, HTMLElement>();
    for (const node of [...this.layer.children] as HTMLElement[]) {
      const i = Number(node.dataset.row);
      if (i >= first && i < last && this.rows[i] && node.dataset.feature === this.rows[i].f.id) {
        keep.set(i, node);
      } else {
        node.remove();
      }
    }
    let prev: HTMLElement | null = null;
    for (let i = first; i < last; i++) {
      const node = keep.get(i) ?? el('div', {});
      this.fill(node, i);
      const next: Element | null = prev ? prev.nextElementSibling : this.layer.firstElementChild;
      if (next !== node) {
        this.layer.insertBefore(node, next);
      }
      prev = node;
    }
    const ids = this.visibleIds().join('\n');
    if (ids !== this.lastShown) {
      this.lastShown = ids;
      this.handlers.shown();
    }
  }

  /** Make ``node`` the row of ``this.rows[i]`` (created once, then only patched). */
  private fill(node: HTMLElement, i: number): void {
    const { f, depth } = this.rows[i];
    const st: FeatureStatus = f.ref ? 'open' : statusOf(this.state, f.id);
    const open = this.expanded.has(f.id);
    const hasKids = !f.ref && f.children.length > 0;
    const cls = ['tree-row', `st-${st}`];
    if (i === this.cursor) cls.push('cursor');
    if (f.id === this.selected && !f.ref) cls.push('selected');
    if (this.linked.has(f.id)) cls.push('linked');
    if (f.ref) cls.push('ref');
    node.className = cls.join(' ');
    const attrs: Record<string, string> = {
      role: 'treeitem', 'data-feature': f.id, 'data-row': String(i), 'data-status': st, 'aria-level': String(depth + 1),
      'aria-selected': String(f.id === this.selected),
      title: `${f.longName}: ${STATUS_WORDS[st]}` + (f.kindText ? `\n${f.kindText}` : ''),
    };
    for (const [k, v] of Object.entries(attrs)) {
      if (node.getAttribute(k) !== v) node.setAttribute(k, v);
    }
    if (hasKids) node.setAttribute('aria-expanded', String(open)); else node.removeAttribute('aria-expanded');
    const indent = this.indent(depth);
    node.style.paddingLeft = `${6 + indent}px`; // (CSSOM: the page's CSP refuses style attributes)
    if (!node.firstChild) {
      node.append(el('span', { class: 'twisty', 'data-act': 'toggle', 'aria-hidden': 'true' }),
        el('span', { class: 'check inc', role: 'checkbox', 'data-act': 'include' }),
        el('span', { class: 'check exc', role: 'button', 'data-act': 'exclude' }, '✕'),
        el('span', { class: 'name' }), el('span', { class: 'tag' }), el('span', { class: 'count' }));
    }
    const [tw, inc, exc, name, tag, count] = [...node.children] as HTMLElement[];
    tw.className = `twisty${hasKids ? '' : ' leaf'}`;
    tw.textContent = hasKids ? (open ? '▾' : '▸') : '';
    const on = st === 'user-in' || st === 'implied-in';
    const off = st === 'user-out' || st === 'implied-out';
    inc.hidden = exc.hidden = Boolean(f.ref);
    inc.className = `check inc${on ? ' on' : ''}`;
    inc.setAttribute('aria-checked', String(on));
    inc.title = st === 'user-in' ? `Undo: include ${f.name}` : `Include ${f.name}`;
    inc.textContent = on ? '✓' : '';
    exc.className = `check exc${off ? ' on' : ''}`;
    exc.title = st === 'user-out' ? `Undo: exclude ${f.name}` : `Exclude ${f.name}`;
    const width = Math.max(80, (this.scroller.clientWidth || 400) - 6 - indent - 260);
    name.textContent = middleEllipsis(f.name, width, '600 13px system-ui, sans-serif');
    const tags: string[] = [];
    if (f.kind === 'optional') tags.push('opt');
    if (f.group && f.group.kind !== 'allOf') tags.push(f.group.text);
    if (f.ref) tags.push('shared');
    tag.textContent = tags.join(' · ');
    const n = this.counts?.features[f.id];
    const rem = this.counts?.remaining ?? null;
    count.textContent = n !== undefined && rem !== null ? `${formatCount(n)} · ${percent(n, rem)}`
      : this.counts && this.counts.remaining !== null ? '…' : '';
  }

  /** The indentation of a level: 16 px a level, less below the tenth, never past 40 % of the
   * panel (a model 40 levels deep keeps its names on screen). */
  private indent(depth: number): number {
    const px = depth <= 10 ? depth * INDENT : 10 * INDENT + (depth - 10) * 4;
    return Math.min(px, Math.max(60, (this.scroller.clientWidth || 400) * 0.4));
  }

  // ------------------------------------------------------------------ input

  private click(ev: MouseEvent): void {
    const target = ev.target as HTMLElement;
    const rowEl = target.closest('.tree-row') as HTMLElement | null;
    if (!rowEl) {
      return;
    }
    const i = Number(rowEl.dataset.row);
    const r = this.rows[i];
    if (!r) {
      return;
    }
    this.cursor = i;
    const act = target.closest('[data-act]')?.getAttribute('data-act');
    if (act === 'toggle') {
      this.toggle(r.f);
    } else if (act === 'include' || act === 'exclude') {
      this.decide(r.f, act === 'include');
    } else {
      this.pick(r.f);
    }
    this.scroller.focus({ preventScroll: true });
  }

  private decide(f: FeatureNode, want: boolean): void {
    if (f.ref) {
      return;
    }
    this.pick(f);
    this.handlers.decide(f.id, nextValue(statusOf(this.state, f.id), want));
  }

  private pick(f: FeatureNode): void {
    const real = this.index.byId.get(f.id) ?? f;
    this.selected = real.id;
    this.handlers.select(real);
    this.schedule();
  }

  private toggle(f: FeatureNode): void {
    if (f.ref || !f.children.length) {
      return;
    }
    if (this.expanded.has(f.id)) {
      this.expanded.delete(f.id);
    } else {
      this.expanded.add(f.id);
    }
    this.flatten();
    this.schedule();
  }

  private key(ev: KeyboardEvent): void {
    const r = this.rows[this.cursor];
    if (!r) {
      return;
    }
    const page = Math.max(1, Math.floor((this.scroller.clientHeight || 400) / ROW_H) - 1);
    let moved = true;
    switch (ev.key) {
      case 'ArrowDown': this.cursor = Math.min(this.rows.length - 1, this.cursor + 1); break;
      case 'ArrowUp': this.cursor = Math.max(0, this.cursor - 1); break;
      case 'PageDown': this.cursor = Math.min(this.rows.length - 1, this.cursor + page); break;
      case 'PageUp': this.cursor = Math.max(0, this.cursor - page); break;
      case 'Home': this.cursor = 0; break;
      case 'End': this.cursor = this.rows.length - 1; break;
      case 'ArrowRight':
        if (!r.f.ref && r.f.children.length && !this.expanded.has(r.f.id)) {
          this.toggle(r.f);
        } else if (!r.f.ref && r.f.children.length) {
          this.cursor += 1;
        }
        break;
      case 'ArrowLeft':
        if (!r.f.ref && this.expanded.has(r.f.id) && r.f.children.length) {
          this.toggle(r.f);
        } else {
          for (let i = this.cursor - 1; i >= 0; i--) {
            if (this.rows[i].depth < r.depth) {
              this.cursor = i;
              break;
            }
          }
        }
        break;
      case ' ': case '+': case 'Enter': case 'i':
        this.decide(r.f, true);
        moved = false;
        break;
      case '-': case 'x': case 'Delete':
        this.decide(r.f, false);
        moved = false;
        break;
      case 'Backspace': case '0':
        if (!r.f.ref && r.f.id in (this.state?.decisions ?? {})) {
          this.pick(r.f);
          this.handlers.decide(r.f.id, null);
        }
        moved = false;
        break;
      case '*':
        this.expandUnder(r.f);
        break;
      default:
        return;
    }
    ev.preventDefault();
    if (moved) {
      const f = this.rows[this.cursor].f;
      this.scrollTo(this.cursor);
      if (!f.ref) {
        this.pick(f);
      }
    }
    this.schedule();
  }

  private expandUnder(f: FeatureNode, limit = 2000): void {
    const todo = [f];
    let n = 0;
    while (todo.length && n < limit) {
      const x = todo.shift() as FeatureNode;
      if (x.ref || !x.children.length) continue;
      this.expanded.add(x.id);
      n += x.children.length;
      todo.push(...x.children);
    }
    this.flatten();
  }

  private scrollTo(i: number): void {
    const top = i * ROW_H;
    const h = this.scroller.clientHeight || 400;
    if (top < this.scroller.scrollTop) {
      this.scroller.scrollTop = top;
    } else if (top + ROW_H > this.scroller.scrollTop + h) {
      this.scroller.scrollTop = top + ROW_H - h;
    }
  }

  // ------------------------------------------------------------------ FeatureView

  setState(state: State): void {
    this.state = state;
    this.schedule();
  }

  setCounts(counts: Counts | null): void {
    this.counts = counts;
    this.schedule();
  }

  visibleIds(): string[] {
    const [first, last] = this.range();
    const out: string[] = [];
    for (let i = first; i < last && i < this.rows.length; i++) {
      if (!this.rows[i].f.ref) out.push(this.rows[i].f.id);
    }
    return out;
  }

  reveal(id: string): void {
    for (const a of this.index.ancestors(id)) {
      this.expanded.add(a);
    }
    this.flatten();
    const i = this.rowIndex.get(id);
    if (i === undefined) {
      return;
    }
    this.cursor = i;
    this.selected = id;
    const h = this.scroller.clientHeight || 400;
    const top = i * ROW_H;
    if (top < this.scroller.scrollTop || top + ROW_H > this.scroller.scrollTop + h) {
      this.scroller.scrollTop = Math.max(0, top - h / 3);
    }
    this.render();
  }

  select(id: string | null): void {
    this.selected = id;
    const i = id ? this.rowIndex.get(id) : undefined;
    if (i !== undefined) {
      this.cursor = i;
    }
    this.schedule();
  }

  setLinked(ids: Set<string>): void {
    this.linked = ids;
    this.schedule();
  }

  expandAll(): void {
    this.expandUnder(this.index.root, 1e9);
    this.schedule();
  }

  collapseAll(): void {
    this.expanded.clear();
    this.expanded.add(this.index.root.id);
    this.flatten();
    this.scroller.scrollTop = 0;
    this.schedule();
  }

  focus(): void {
    this.scroller.focus({ preventScroll: true });
  }

  destroy(): void {
    this.resize.disconnect();
    if (this.frame) cancelAnimationFrame(this.frame);
    this.scroller.remove();
  }

  /** rows currently laid out (tests: the tree is virtualised) */
  get rowCount(): number {
    return this.rows.length;
  }
}
