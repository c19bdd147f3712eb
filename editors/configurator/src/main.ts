// The configurator's page: the features (a diagram as the thesis draws it, or an indented tree for
// big models) beside the computation graph and the details of what is selected; the problems that
// can still occur and your decisions below. A thin client: every answer comes from
// tvl_lsp/configurator through the host (tvl-lsp ui over HTTP, or the VS Code extension and the
// language server).
import * as actions from './actions';
import { countWithExact, renderFeature, renderGraphItem, renderNothing } from './details';
import { Diagram, firstLevelScale } from './diagram';
import { basename, conditionNames, el, exactCount, formatCount } from './format';
import { GraphView, KINDS } from './graph';
import { renderDecisions, renderProblems } from './lists';
import { FeatureIndex, FeatureView } from './model';
import type { Page, Selection } from './page';
import { TreeView } from './tree';
import { makeTransport, Transport } from './transport';
import type {
  Counts, DecideResult, Explanation, FeatureNode, GraphEdge, GraphElement, GraphJson, ModelJson, Problem, ProblemsJson,
  Refusal, State, Status, Targets,
} from './types';
import { locLink, menu, redraw, relative, setWhere, sleep, tabs, toast } from './ui';

const t: Transport = makeTransport();
const root = document.getElementById('app') as HTMLElement;
/** above this many features the tree is shown first (the user can switch) */
export const TREE_ABOVE = 80;
/** the diagram is not shown first when its first level would be drawn smaller than this */
const MIN_FIRST_LEVEL_SCALE = 0.5;

function storageGet(key: string): string | null {
  try {
    return window.localStorage.getItem(key);
  } catch {
    return null;
  }
}

function storageSet(key: string, value: string): void {
  try {
    window.localStorage.setItem(key, value);
  } catch {
    // no storage in this webview: the choice lasts for the page
  }
}

function decisionsKey(d: Record<string, boolean>): string {
  return JSON.stringify(Object.entries(d).sort());
}

class App implements Page {
  readonly t = t;
  state: State;
  counts: Counts | null = null;
  view!: FeatureView;
  graph: GraphView | null = null;
  graphJson: GraphJson | null = null;
  graphStatus: Record<string, Status> = {};
  selection: Selection | null = null;
  problems: Problem[] | null = null;
  problemStatus: Record<string, Status> = {};
  showRuledOut = false;
  showAllProblems = false;
  history: Record<string, boolean>[] = [];
  /** counts the states applied: an answer asked for before another state came is stale */
  stateSeq = 0;
  index: FeatureIndex;
  private countSeq = 0;
  private countsKey = '';
  private countStop = false; // the model will not be counted (compile budget spent)
  private countStatus = 'pending';
  private countMessage = '';
  private moreTimer = 0;
  private explained = new Map<string, Explanation>();
  private busyN = 0;
  private byFeature = new Map<string, GraphElement[]>();
  private generateMenu!: ReturnType<typeof menu>;
  closed = false;

  constructor(public model: ModelJson, private targets: Targets | null) {
    this.state = model.state;
    this.index = new FeatureIndex(model.tree);
  }

  // ------------------------------------------------------------------ Page

  busy(delta: number): void {
    this.busyN += delta;
    document.body.classList.toggle('busy', this.busyN > 0);
  }

  async reload(): Promise<void> {
    await load(this.model.model); // the targets again: a pairing chosen on the page changes them
  }

  async decide(feature: string, value: boolean | null): Promise<void> {
    const before = { ...this.state.decisions };
    this.busy(1);
    try {
      const r = await t.request<DecideResult>('decide', { model: this.model.model, feature, value, counts: this.wanted() });
      if (this.closed) return;
      if (!r.refused) {
        this.history.push(before);
      }
      this.applyState(r.state);
      if (r.refused) {
        showRefusal(r.refused);
      } else {
        document.querySelectorAll('.toast.refusal').forEach((n) => n.remove());
        this.takeCounts(r.counts);
      }
    } catch (e) {
      toast((e as Error).message, 'error');
    } finally {
      this.busy(-1);
    }
  }

  async setDecisions(decisions: Record<string, boolean>, what: string): Promise<boolean> {
    const before = { ...this.state.decisions };
    this.busy(1);
    try {
      const r = await t.request<DecideResult>('set', { model: this.model.model, decisions, counts: this.wanted() });
      if (this.closed) return false;
      if (what !== 'undo') {
        this.history.push(before);
      }
      this.applyState(r.state);
      document.querySelectorAll('.toast.refusal').forEach((n) => n.remove());
      if (r.refused) {
        showRefusal(r.refused);
      }
      this.takeCounts(r.counts);
      return !r.refused;
    } catch (e) {
      toast((e as Error).message, 'error');
      return false;
    } finally {
      this.busy(-1);
    }
  }

  async explain(feature: string): Promise<Explanation | null> {
    const key = decisionsKey(this.state.decisions) + '|' + feature;
    const hit = this.explained.get(key);
    if (hit) {
      return hit;
    }
    try {
      const x = await t.request<Explanation>('explain', { model: this.model.model, feature });
      this.explained.set(key, x);
      if (this.explained.size > 500) {
        this.explained.clear();
      }
      return x;
    } catch {
      return null;
    }
  }

  revealFeature(id: string): void {
    const f = this.index.byId.get(id);
    if (!f) {
      return;
    }
    document.body.dataset.pane = 'features';
    this.view.reveal(id);
    this.selectFeature(f);
  }

  selectGraph(id: string): void {
    const e = this.graphJson?.elements.find((x) => x.id === id);
    if (!e) {
      return;
    }
    document.body.dataset.pane = 'graph';
    this.graph?.show(id);
    this.selectGraphItem(e, 'element');
  }

  graphLinksOf(feature: string): GraphElement[] {
    return this.byFeature.get(feature) ?? [];
  }

  countNote(): string {
    if (this.countStatus === 'gave-up' || this.countStatus === 'failed') {
      return this.countMessage.startsWith('not counted') ? this.countMessage
        : 'not counted: ' + (this.countMessage || 'the model could not be counted');
    }
    if (this.countStatus === 'compiling') {
      return 'counting… (the model is being compiled)';
    }
    return 'counting…';
  }

  // ------------------------------------------------------------------ selection and details

  selectFeature(f: FeatureNode): void {
    this.selection = { kind: 'feature', id: f.id };
    this.view.select(f.id);
    const linked = new Set(this.graphLinksOf(f.id).map((e) => e.id));
    this.graph?.setLinked(linked);
    this.view.setLinked(new Set());
    redraw('details', () => renderFeature(this, f));
    this.askCount(f.id);
  }

  selectGraphItem(e: GraphElement | GraphEdge, kind: 'element' | 'edge'): void {
    this.selection = { kind, id: e.id };
    this.graph?.setLinked(new Set());
    const names = new Set(conditionNames(e.condition).filter((n) => this.index.byId.has(n)));
    this.view.setLinked(names);
    this.view.select(null);
    redraw('details', () => renderGraphItem(this, e, kind));
  }

  /** Refresh the details of what is selected (after every decision and every count). */
  refreshDetails(): void {
    redraw('details', () => this.drawDetails());
  }

  private drawDetails(): void {
    const s = this.selection;
    if (!s) {
      return;
    }
    if (s.kind === 'feature') {
      const f = this.index.byId.get(s.id);
      if (f) renderFeature(this, f);
      return;
    }
    const e = s.kind === 'element' ? this.graphJson?.elements.find((x) => x.id === s.id)
      : this.graphJson?.edges.find((x) => x.id === s.id);
    if (e) renderGraphItem(this, e, s.kind);
  }

  // ------------------------------------------------------------------ state

  applyState(state: State): void {
    this.stateSeq++;
    this.state = state;
    if (state.problems) {
      this.problemStatus = state.problems;
    }
    this.view.setState(state);
    renderProblems(this, false);
    renderDecisions(this);
    if (state.graph) {
      this.graphStatus = state.graph;
      void this.graph?.setStatus(state.graph);
    }
    this.updateGenerate();
    document.body.dataset.complete = String(state.complete);
    this.refreshDetails();
  }

  updateGenerate(): void {
    const m = this.generateMenu;
    if (!m) return;
    const noLaunch = !this.model.launch;
    m.button.disabled = noLaunch;
    m.button.title = noLaunch
      ? `${basename(this.model.model)} configures no launch file: choose one in the graph panel first`
      : 'write configuration launch files (the launch file with every feature arg set) for products';
    const s = this.state;
    m.update('current', !s.complete, s.complete ? 'the configuration launch file of this product'
      : `decide the ${s.open.length} open feature(s) first (or use Configuration ▸ Complete)`);
  }

  // ------------------------------------------------------------------ counts

  private setCountStatus(state: string, text: string, title = '', progress: number | null = null): void {
    this.countStatus = state;
    const s = document.getElementById('count-status') as HTMLElement | null;
    if (s) {
      s.dataset.state = state;
      s.textContent = text;
      s.title = title;
    }
    const bar = document.getElementById('count-progress') as HTMLProgressElement | null;
    if (bar) {
      bar.hidden = progress === null;
      if (progress !== null) bar.value = progress;
    }
    document.body.dataset.counts = state;
  }

  /** Counts that came with a decision's answer (the model is compiled); else ask for them. */
  takeCounts(c: Counts | undefined): void {
    if (!c || c.pending || this.countStop) {
      void this.refreshCounts();
      return;
    }
    this.countSeq++; // an older request in flight is stale now
    this.countsKey = decisionsKey(this.state.decisions);
    this.counts = c;
    this.view.setCounts(c);
    this.showCount(c);
    this.refreshDetails();
  }

  /** Counts for the features on screen (and the selected one) under the current decisions. */
  async refreshCounts(): Promise<void> {
    if (this.countStop) {
      this.view.setCounts(this.counts);
      this.refreshDetails();
      return;
    }
    const seq = ++this.countSeq;
    const rem = document.getElementById('remaining') as HTMLElement;
    rem.classList.add('pending');
    this.setCountStatus('pending', '');
    const key = decisionsKey(this.state.decisions);
    let delay = 100;
    try {
      for (;;) {
        const c = await t.request<Counts>('counts', { model: this.model.model, features: this.wanted(), timeout: 20, wait: 0 });
        if (seq !== this.countSeq || this.closed) {
          return;
        }
        if (c.pending) {
          const secs = c.seconds ?? 0;
          const budget = c.budget ?? 0;
          this.countMessage = c.message ?? '';
          this.setCountStatus('compiling', ` · compiling for counts… ${Math.round(secs)} s` +
            (budget ? ` of ${Math.round(budget)} s` : ''), c.message ?? '', budget ? Math.min(1, secs / budget) : null);
          await sleep(delay);
          delay = Math.min(1000, delay * 1.6);
          if (seq !== this.countSeq || this.closed) {
            return;
          }
          continue;
        }
        this.countsKey = key;
        this.counts = c;
        this.view.setCounts(c);
        this.showCount(c);
        this.refreshDetails();
        return;
      }
    } catch (e) {
      if (seq === this.countSeq) {
        rem.classList.remove('pending');
        this.setCountStatus('failed', ' · counting failed', (e as Error).message);
        toast(`Counting failed: ${(e as Error).message}`, 'error');
      }
    }
  }

  private showCount(c: Counts): void {
    const rem = document.getElementById('remaining') as HTMLElement;
    const tot = document.getElementById('total') as HTMLElement;
    rem.classList.remove('pending');
    this.countMessage = c.message ?? '';
    if (c.status === 'gave-up') {
      this.countStop = true;
      rem.textContent = '—';
      rem.dataset.remaining = '';
      tot.textContent = '—';
      this.setCountStatus('gave-up', ' · not counted', c.message ?? '');
      toast(el('div', { class: 'gave-up' }, `${c.message}. The configurator works on without counts: decisions, what they imply, ` +
        'refusals, the graph and the problems are all still exact.'), 'info', true);
      return;
    }
    rem.textContent = formatCount(c.remaining);
    rem.title = c.remaining ? `${exactCount(c.remaining)} (click for every digit)` : 'no answer in time';
    rem.dataset.remaining = c.remaining ?? '';
    tot.textContent = formatCount(c.total);
    tot.title = c.total ? exactCount(c.total) : '';
    if (c.remaining === null) {
      this.setCountStatus('failed', ' · not counted', c.message ?? '');
    } else {
      this.setCountStatus('ready', c.complete ? '' : ' · some features not counted in time',
        c.engine ? `counted by ${c.engine}${c.message ? ` (${c.message})` : ''}` : '');
    }
  }

  /** The features whose counts are shown: on screen, and the selected one. */
  wanted(): string[] {
    const ids = this.view.visibleIds();
    if (this.selection?.kind === 'feature' && !ids.includes(this.selection.id)) {
      ids.push(this.selection.id);
    }
    return ids;
  }

  /** The view shows other features: ask for the counts it lacks (same decisions). */
  shown(): void {
    if (this.countStop || !this.counts || this.countsKey !== decisionsKey(this.state.decisions)) {
      return;
    }
    clearTimeout(this.moreTimer);
    this.moreTimer = window.setTimeout(() => void this.moreCounts(), 60);
  }

  askCount(id: string): void {
    if (this.counts && !(id in this.counts.features)) {
      this.shown();
    }
  }

  private async moreCounts(): Promise<void> {
    const c = this.counts;
    const key = decisionsKey(this.state.decisions);
    if (!c || this.countsKey !== key) {
      return;
    }
    const missing = this.wanted().filter((x) => !(x in c.features));
    if (!missing.length) {
      return;
    }
    const seq = this.countSeq;
    try {
      const got = await t.request<Counts>('counts', { model: this.model.model, features: missing, timeout: 20, wait: 0 });
      if (seq !== this.countSeq || this.countsKey !== key || got.pending || got.remaining === null) {
        return;
      }
      this.counts = { ...c, features: { ...c.features, ...got.features } };
      this.view.setCounts(this.counts);
      this.refreshDetails();
    } catch {
      // the next decision asks again
    }
  }

  // ------------------------------------------------------------------ the graph

  indexGraph(g: GraphJson): void {
    this.byFeature.clear();
    for (const e of g.elements) {
      for (const n of conditionNames(e.condition)) {
        if (this.index.byId.has(n)) {
          const lst = this.byFeature.get(n) ?? [];
          lst.push(e);
          this.byFeature.set(n, lst);
        }
      }
    }
  }

  setGenerateMenu(m: ReturnType<typeof menu>): void {
    this.generateMenu = m;
  }
}

let app: App | null = null;

function showRefusal(r: Refusal): void {
  document.querySelectorAll('.toast.refusal').forEach((n) => n.remove());
  const body = el('div', { class: 'refusal-body' },
    el('div', { class: 'refusal-msg' }, `${r.value ? 'Include' : 'Exclude'} ${r.feature}: refused.`));
  const mine = Object.entries(r.conflictsWith);
  if (mine.length) {
    body.append(el('div', {}, 'It conflicts with your decision' + (mine.length > 1 ? 's' : '') + ' to ' +
      mine.map(([f, v]) => `${v ? 'include' : 'exclude'} ${f}`).join(', ') + '.'));
  } else {
    body.append(el('div', {}, `No product ${r.value ? 'includes' : 'excludes'} ${r.feature}.`));
  }
  if (r.because.length) {
    const ul = el('ul', { class: 'because' });
    r.because.forEach((b) => ul.append(el('li', {}, b.label, ' ', b.location ? locLink(b.location) : null)));
    body.append(el('div', {}, 'Because:'), ul);
  }
  const item = toast(body, 'refusal', true);
  item.setAttribute('data-feature', r.feature);
  item.setAttribute('title', r.message);
}

// ------------------------------------------------------------------ header

function header(a: App, targets: Targets | null, m: ModelJson): HTMLElement {
  const picker = el('select', { id: 'model-picker', title: 'the feature model to configure' });
  const models = targets?.models ?? [{ model: m.model, launches: m.launches }];
  for (const x of models) {
    const o = el('option', { value: x.model }, relative(x.model) + (x.launches.length ? '' : ' (no launch file)'));
    if (x.model === m.model) {
      o.selected = true;
    }
    picker.append(o);
  }
  picker.addEventListener('change', () => void load(picker.value, targets));
  const search = el('input', {
    id: 'search', type: 'search', placeholder: 'Find a feature  ( / )', autocomplete: 'off', 'aria-label': 'find a feature',
  }) as HTMLInputElement;
  const results = el('ul', { id: 'search-results', role: 'listbox' });
  let active = 0;
  let found: FeatureNode[] = [];
  const pick = (f: FeatureNode) => {
    a.revealFeature(f.id);
    results.replaceChildren();
  };
  const runSearch = () => {
    results.replaceChildren();
    found = a.index.find(search.value);
    active = 0;
    found.forEach((f, i) => {
      const li = el('li', { role: 'option', 'data-feature': f.id, class: i === 0 ? 'active' : '' }, f.name,
        f.longName !== f.name ? el('span', { class: 'muted' }, ' ' + f.longName) : null);
      li.addEventListener('mousedown', (ev) => {
        ev.preventDefault();
        pick(f);
      });
      results.append(li);
    });
    if (search.value.trim() && !found.length) {
      results.append(el('li', { class: 'muted none' }, 'no feature has this name'));
    }
  };
  search.addEventListener('input', runSearch);
  search.addEventListener('keydown', (ev) => {
    if (ev.key === 'ArrowDown' || ev.key === 'ArrowUp') {
      ev.preventDefault();
      active = Math.max(0, Math.min(found.length - 1, active + (ev.key === 'ArrowDown' ? 1 : -1)));
      [...results.children].forEach((c, i) => c.classList.toggle('active', i === active));
    } else if (ev.key === 'Enter') {
      const f = found[active] ?? a.index.find(search.value, 1)[0];
      if (f) {
        pick(f);
      }
    } else if (ev.key === 'Escape') {
      results.replaceChildren();
    }
  });
  search.addEventListener('blur', () => setTimeout(() => results.replaceChildren(), 150));

  const cfg = menu('configuration', 'Configuration', [
    { id: 'complete-minimal', label: 'Complete: smallest product', title: 'decide every open feature: the product with the fewest features that respects your decisions', run: () => void actions.complete(a, 'minimal') },
    { id: 'complete-random', label: 'Complete: random product', title: 'decide every open feature: a product drawn at random among the remaining ones', run: () => void actions.complete(a, 'random') },
    { id: 'save', label: 'Save…', title: 'save your decisions next to the model (tvl-lsp JSON, FeatureIDE XML or .uvl.json)', run: () => void actions.saveDialog(a) },
    { id: 'load', label: 'Load…', title: 'load a saved configuration: its decisions replace yours', run: () => void actions.loadDialog(a) },
    { id: 'reset', label: 'Reset', title: 'forget every decision', run: () => void a.setDecisions({}, 'reset') },
  ]);
  const gen = menu('generate', 'Generate', [
    { id: 'current', label: 'This product', title: 'the configuration launch file of the product you configured', run: () => void actions.generate(a, 'current') },
    { id: 'completions', label: 'Every remaining product', title: 'one configuration launch file per remaining product', run: () => void actions.generate(a, 'completions') },
    { id: 'sample', label: 'Pairwise sample', title: 'a sample of the remaining products covering every pair of feature choices', run: () => void actions.generate(a, 'sample') },
    { id: 'all', label: 'Every product of the model', title: 'one configuration launch file per product, whatever your decisions', run: () => void actions.generate(a, 'all') },
  ]);
  gen.root.querySelectorAll('[data-action]').forEach((b) => b.setAttribute('data-mode', b.getAttribute('data-action') ?? ''));
  a.setGenerateMenu(gen);

  const remaining = el('span', { id: 'remaining', 'data-remaining': '', role: 'button', tabindex: '0' }, '…');
  const exact = el('div', { id: 'exact-count', hidden: '' });
  remaining.addEventListener('click', () => {
    const c = a.counts;
    if (!c?.remaining) return;
    exact.hidden = !exact.hidden;
    exact.replaceChildren(el('div', {}, el('strong', {}, 'Remaining products'), ' ', countWithExact(c.remaining)),
      el('code', {}, exactCount(c.remaining)), el('div', { class: 'muted' }, `of ${exactCount(c.total ?? '')}`));
  });
  const paneSwitch = el('div', { class: 'pane-switch', role: 'tablist' });
  for (const [k, label] of [['features', 'Features'], ['graph', 'Graph']]) {
    const b = el('button', { 'data-pane': k }, label);
    b.addEventListener('click', () => {
      document.body.dataset.pane = k;
    });
    paneSwitch.append(b);
  }
  return el('header', {},
    el('div', { class: 'title' }, el('strong', {}, 'TVL configurator'),
      models.length > 1 ? picker : el('span', { class: 'muted model-name' }, relative(m.model))),
    el('div', { id: 'count', 'aria-live': 'polite' },
      remaining, ' of ', el('span', { id: 'total' }, '…'), ' products',
      el('span', { id: 'count-status', class: 'muted', 'data-state': 'pending' }, ''),
      el('progress', { id: 'count-progress', max: '1', value: '0', hidden: '' }), exact),
    el('div', { class: 'search' }, search, results),
    el('div', { class: 'actions' }, paneSwitch, cfg.root, gen.root),
  );
}

// ------------------------------------------------------------------ panels

function legend(): HTMLElement {
  const item = (cls: string, label: string) => el('span', { class: `legend-item ${cls}` }, el('i', {}), label);
  return el('details', { class: 'legend-box' }, el('summary', { title: 'what the colours and marks mean' }, 'Legend'),
    el('div', { class: 'legend' },
      item('st-user-in', 'included (you)'), item('st-implied-in', 'included (implied)'),
      item('st-user-out', 'excluded (you)'), item('st-implied-out', 'excluded (implied)'), item('st-open', 'open'),
      el('span', { class: 'legend-item' }, el('b', { class: 'dot mandatory' }), 'mandatory'),
      el('span', { class: 'legend-item' }, el('b', { class: 'dot optional' }), 'optional'),
      el('span', { class: 'legend-item' }, 'arcs: oneOf hollow, someOf filled'),
      el('span', { class: 'legend-item' }, 'keys: / find, f fit, + − zoom; tree: arrows, space include, x exclude')));
}

function featureToolbar(a: App, box: HTMLElement, m: ModelJson): HTMLElement {
  const seg = el('div', { class: 'segmented', role: 'tablist', 'aria-label': 'feature view' });
  for (const [k, label] of [['diagram', 'Diagram'], ['tree', 'Tree']] as const) {
    const b = el('button', { 'data-view': k, role: 'tab', title: k === 'tree' ? 'an indented tree (big models)' : 'the feature diagram (FODA, as the thesis draws it)' }, label);
    b.addEventListener('click', () => {
      storageSet(`tvl-view:${m.model}`, k);
      setView(a, box, k);
    });
    seg.append(b);
  }
  const expand = el('button', { id: 'expand-all', class: 'small', title: 'expand every feature (the diagram: up to 400)' }, 'Expand');
  expand.addEventListener('click', () => a.view.expandAll());
  const collapse = el('button', { id: 'collapse-all', class: 'small', title: 'collapse to the first level' }, 'Collapse');
  collapse.addEventListener('click', () => a.view.collapseAll());
  return el('div', { class: 'panel-head' }, el('strong', {}, 'Features'),
    el('span', { class: 'muted' }, ` ${m.name} · ${m.features.toLocaleString('en-US')} features`), seg, expand, collapse, legend());
}

function setView(a: App, box: HTMLElement, kind: 'diagram' | 'tree'): void {
  if (a.view?.kind === kind) {
    return;
  }
  a.view?.destroy();
  box.replaceChildren();
  const handlers = {
    decide: (f: string, v: boolean | null) => void a.decide(f, v),
    select: (f: FeatureNode) => a.selectFeature(f),
    shown: () => a.shown(),
  };
  a.view = kind === 'tree' ? new TreeView(box, a.index, handlers) : new Diagram(box, a.index, handlers);
  document.body.dataset.view = kind;
  document.querySelectorAll('.segmented [data-view]').forEach((b) =>
    b.setAttribute('aria-selected', String(b.getAttribute('data-view') === kind)));
  a.view.setState(a.state);
  a.view.setCounts(a.counts);
  if (a.selection?.kind === 'feature') {
    a.view.reveal(a.selection.id);
  }
  a.shown();
}

function graphToolbar(a: App): HTMLElement {
  const search = el('input', { type: 'search', id: 'graph-search', placeholder: 'Find in the graph', 'aria-label': 'find in the graph' }) as HTMLInputElement;
  const hits = el('span', { class: 'muted', id: 'graph-hits' });
  search.addEventListener('input', () => {
    const ids = a.graph?.search(search.value) ?? [];
    hits.textContent = search.value.trim() ? `${ids.length} found` : '';
  });
  search.addEventListener('keydown', (ev) => {
    if (ev.key === 'Enter') {
      const ids = a.graph?.search(search.value) ?? [];
      if (ids.length) a.selectGraph(ids[0]);
    }
  });
  const kinds = el('div', { class: 'kinds', role: 'group', 'aria-label': 'show kinds' });
  const hidden = new Set<string>();
  for (const k of KINDS) {
    const cb = el('input', { type: 'checkbox', 'data-kind': k }) as HTMLInputElement;
    cb.checked = true;
    cb.addEventListener('change', () => {
      if (cb.checked) hidden.delete(k); else hidden.add(k);
      a.graph?.setHiddenKinds(new Set(hidden));
    });
    kinds.append(el('label', { class: `legend-item g-${k}`, title: `show ${k === 'include' ? 'includes not followed' : k + 's'}` }, cb, el('i', {}),
      k === 'param' ? 'param' : k));
  }
  const group = el('input', { type: 'checkbox', id: 'group-ns' }) as HTMLInputElement;
  group.addEventListener('change', () => void a.graph?.setGrouped(group.checked));
  const removed = el('input', { type: 'checkbox', id: 'show-removed' }) as HTMLInputElement;
  removed.addEventListener('change', () => {
    if (a.graph) {
      a.graph.showRemoved = removed.checked;
      a.graph.restyle();
    }
  });
  return el('div', { class: 'graph-tools' }, search, hits, kinds,
    el('label', { class: 'toggle', title: 'lay the graph out with a box per namespace' }, group, ' namespaces'),
    el('label', { class: 'toggle', title: 'show what your decisions removed, faded' }, removed, ' removed'),
    el('span', { class: 'legend-item g-dashed', title: 'dashed: in some remaining products only' }, el('i', {}), 'in some'));
}

function noTopicsNote(g: GraphJson): HTMLElement | null {
  const n = g.noTopics;
  if (!n) {
    return null;
  }
  const what = el('ul', {},
    el('li', {}, 'node hints in a HAROS project file (', el('code', {}, 'nodes: {pkg/type: {advertise: {/topic: msg/Type}}}'), ')',
      n.types.length ? ` for ${n.types.slice(0, 6).join(', ')}${n.types.length > 6 ? ', …' : ''}` : ''),
    el('li', {}, 'the nodes\' packages in the workspace, where tvl-lsp reads their publishers and subscribers from the sources' +
      (n.sourcesAway.length ? ` (not in it: ${n.sourcesAway.slice(0, 6).join(', ')}${n.sourcesAway.length > 6 ? ', …' : ''})` : '')));
  const close = el('button', { class: 'close', title: 'dismiss' }, '×');
  const box = el('details', { class: 'graph-note', id: 'no-topics' },
    el('summary', {}, el('strong', {}, 'No topics: '), 'nothing says what these nodes publish or subscribe to. What would add them?'),
    what, close);
  close.addEventListener('click', () => box.remove());
  return box;
}

async function loadGraph(a: App, box: HTMLElement, panel: HTMLElement): Promise<void> {
  if (!a.model.launch) {
    await actions.pairPanel(a, box);
    document.body.dataset.graph = 'none';
    return;
  }
  const wait = el('div', { class: 'empty' }, 'Building the computation graph of every product…');
  box.append(wait);
  try {
    const g = await t.request<GraphJson>('graph', { model: a.model.model });
    if (app !== a) {
      return;
    }
    wait.remove();
    a.graphJson = g;
    a.indexGraph(g);
    const note = noTopicsNote(g);
    if (note) panel.insertBefore(note, box);
    a.graph = new GraphView(box, g, { select: (e, k) => a.selectGraphItem(e, k) }, () => t.layoutWorker());
    const seq = a.stateSeq;
    const st = a.state.graph ? a.state : await t.request<State>('state', { model: a.model.model });
    if (app !== a) {
      return;
    }
    // (a decision answered meanwhile brought the newer status)
    a.graphStatus = (a.stateSeq !== seq ? a.state.graph : null) ?? st.graph ?? g.status ?? {};
    await a.graph.setStatus(a.graphStatus);
    document.body.dataset.graph = 'ready';
    a.refreshDetails();
  } catch (e) {
    wait.textContent = `No computation graph: ${(e as Error).message}`;
  }
}

async function loadProblems(a: App): Promise<void> {
  try {
    const r = await t.request<ProblemsJson>('problems', { model: a.model.model });
    if (app !== a) {
      return;
    }
    a.problems = r.problems;
    a.problemStatus = r.status ?? {};
    // the problems' status under the current decisions: a state asked for before a decision's
    // answer came in is older than it (it would bring back the decisions before the click)
    for (let tries = 0; tries < 5 && app === a; tries++) {
      const seq = a.stateSeq;
      const st = await t.request<State>('state', { model: a.model.model });
      if (a.stateSeq === seq && app === a) {
        a.applyState(st);
        break;
      }
    }
    renderProblems(a);
    document.body.dataset.problems = 'ready';
  } catch (e) {
    if (app === a) {
      a.problems = [];
      renderProblems(a);
      toast(`Checking the files failed: ${(e as Error).message}`, 'error');
    }
  }
}

function defaultView(m: ModelJson, index: FeatureIndex, width: number): 'diagram' | 'tree' {
  const saved = storageGet(`tvl-view:${m.model}`);
  if (saved === 'diagram' || saved === 'tree') {
    return saved;
  }
  if (m.features > TREE_ABOVE) {
    return 'tree';
  }
  return firstLevelScale(index, width) < MIN_FIRST_LEVEL_SCALE ? 'tree' : 'diagram';
}

async function load(modelPath?: string | null, targets?: Targets | null): Promise<void> {
  root.classList.add('loading');
  try {
    if (targets === undefined) {
      targets = t.kind === 'http' ? await t.request<Targets>('targets') : null;
      modelPath = modelPath ?? targets?.initial ?? undefined;
    }
    if (targets) {
      setWhere({ transport: t, roots: targets.roots, model: () => app?.model.model });
    }
    const m = await t.request<ModelJson>('model', modelPath ? { model: modelPath } : {});
    if (app) app.closed = true;
    const a = new App(m, targets ?? null);
    app = a;
    setWhere({ transport: t, roots: m.roots, model: () => app?.model.model });
    root.classList.remove('loading');
    root.replaceChildren();
    const featureBox = el('section', { id: 'diagram', class: 'features', 'aria-label': 'features' });
    const graphBox = el('section', { id: 'graph', 'aria-label': 'computation graph' });
    const left = el('div', { id: 'left' }, featureToolbar(a, featureBox, m), featureBox);
    const graphPanel = el('div', { id: 'side' },
      el('div', { class: 'panel-head' }, el('strong', {}, 'Computation graph'),
        el('span', { class: 'muted' }, m.launch ? ' ' + relative(m.launch) : ' (no launch file)'), m.launch ? graphToolbar(a) : null),
      graphBox);
    const details = el('section', { id: 'details', 'aria-label': 'details', 'aria-live': 'polite' });
    const problems = el('section', { id: 'problems', 'aria-label': 'problems' });
    const decisions = el('section', { id: 'decisions', 'aria-label': 'your decisions' });
    const bottomTabs = tabs('bottom-tabs', [['problems', 'Problems', problems], ['decisions', 'Decisions', decisions]]);
    const bottom = el('div', { id: 'bottom' }, bottomTabs.bar, problems, decisions);
    root.append(header(a, targets ?? null, m), el('main', {}, left, graphPanel, details), bottom,
      el('div', { id: 'toasts', 'aria-live': 'polite' }));
    document.body.dataset.pane = 'features';
    document.body.classList.toggle('no-launch', !m.launch);
    renderNothing();
    const width = featureBox.getBoundingClientRect().width || window.innerWidth / 2;
    setView(a, featureBox, defaultView(m, a.index, width));
    a.applyState(m.state);
    renderProblems(a);
    if (m.state.void) {
      toast(el('div', { class: 'void' }, el('strong', {}, 'This model has no product'),
        ' (it is void): every decision is refused with the reason. The problems below say what makes it void.'), 'error', true);
    }
    document.body.dataset.ready = 'diagram';
    void a.refreshCounts();
    void loadGraph(a, graphBox, graphPanel);
    void loadProblems(a);
  } catch (e) {
    root.classList.remove('loading');
    const others = (targets?.models ?? []).filter((x) => x.model !== modelPath);
    const pick = el('select', { id: 'model-picker', 'aria-label': 'another model' });
    pick.append(el('option', { value: '' }, 'open another model of the workspace…'));
    others.forEach((x) => pick.append(el('option', { value: x.model }, relative(x.model))));
    pick.addEventListener('change', () => pick.value && void load(pick.value, targets));
    root.replaceChildren(el('div', { class: 'fatal' },
      el('h2', {}, modelPath ? `The configurator cannot open ${relative(modelPath)}` : 'The configurator cannot open this workspace'),
      el('p', {}, (e as Error).message), others.length ? pick : null));
  }
}

document.addEventListener('keydown', (ev) => {
  const target = ev.target as Element | null;
  if (target?.closest?.('input,select,textarea') || ev.ctrlKey || ev.metaKey || ev.altKey) {
    return;
  }
  if (ev.key === '/') {
    ev.preventDefault();
    (document.getElementById('search') as HTMLInputElement | null)?.focus();
  } else if (app?.view.kind === 'diagram' && !target?.closest?.('.tree, svg') && ['f', '+', '=', '-'].includes(ev.key)) {
    // the zoom keys work wherever the focus is not in a field or in the other view
    const d = app.view as Diagram;
    if (ev.key === 'f') d.fit(); else d.zoomBy(ev.key === '-' ? 1 / 1.3 : 1.3);
  }
});

t.onRefresh((reload) => {
  if (!app || reload) {
    void load();
    return;
  }
  void (async () => {
    const a = app;
    if (!a) return;
    const s = await t.request<State>('state', { model: a.model.model });
    a.applyState(s);
    void a.refreshCounts();
  })();
});

void load();
