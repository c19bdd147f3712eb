// What the header's menus do: complete the configuration, save and load it (next to the model, as
// tvl-lsp JSON, FeatureIDE XML or uvls .uvl.json), generate configuration launch files (saying
// how many, which limit cut the rest, each file openable), and pair the model with a launch file
// when no pairing rule names one.
import { el, formatCount } from './format';
import type { Page } from './page';
import type { CompleteResult, ConfigsJson, GenerateResult, LaunchesJson, LoadResult, SaveResult } from './types';
import { fileLink, modal, relative, toast } from './ui';

const FORMAT_LABEL: Record<string, string> = {
  json: 'tvl-lsp JSON (.config.json)',
  featureide: 'FeatureIDE XML (.xml)',
  uvl: 'UVL language server (.uvl.json)',
};

export async function complete(page: Page, how: 'minimal' | 'random'): Promise<void> {
  const before = { ...page.state.decisions };
  page.busy(1);
  try {
    const r = await page.t.request<CompleteResult>('complete', {
      model: page.model.model, how, seed: Math.floor(Math.random() * 1e9), counts: page.wanted(),
    });
    page.history.push(before);
    page.applyState(r.state);
    page.takeCounts(r.counts);
    const added = Object.entries(r.added);
    const inc = added.filter(([, v]) => v).length;
    const undo = el('button', { class: 'small', id: 'undo-complete' }, 'Undo');
    undo.addEventListener('click', () => {
      item.remove();
      void page.setDecisions(before, 'undo');
    });
    const item = toast(el('div', { class: 'completed', 'data-added': String(added.length) },
      added.length
        ? `Completed (${how === 'minimal' ? 'the smallest product' : 'a random product'}): ${added.length} open feature${added.length === 1 ? '' : 's'} decided, ${inc} included. `
        : 'Nothing to complete: every feature is decided. ',
      undo), 'info');
  } catch (e) {
    toast(`Complete: ${(e as Error).message}`, 'error');
  } finally {
    page.busy(-1);
  }
}

export async function saveDialog(page: Page): Promise<void> {
  const stem = page.model.model.split('/').pop()?.replace(/\.[^.]+$/, '') ?? 'configuration';
  const name = el('input', { type: 'text', id: 'save-name', value: stem, 'aria-label': 'configuration name' }) as HTMLInputElement;
  const fmt = el('select', { id: 'save-format', 'aria-label': 'format' }) as HTMLSelectElement;
  for (const [k, v] of Object.entries(FORMAT_LABEL)) {
    fmt.append(el('option', { value: k }, v));
  }
  const where = el('div', { class: 'muted' });
  const folder = page.model.model.replace(/\/[^/]+$/, '');
  const update = () => {
    const suffix = fmt.value === 'json' ? '.config.json' : fmt.value === 'uvl' ? '.uvl.json' : '.xml';
    where.textContent = `next to the model: ${relative(folder)}/${(name.value.trim() || stem).replace(/[^A-Za-z0-9_.-]+/g, '_')}${suffix}`;
  };
  name.addEventListener('input', update);
  fmt.addEventListener('change', update);
  update();
  const go = el('button', { class: 'primary', id: 'save-go' }, 'Save');
  const n = Object.keys(page.state.decisions).length;
  const body = el('div', { class: 'form' },
    el('p', {}, `Your ${n} decision${n === 1 ? '' : 's'} (what they imply is derived again when you load it).`),
    el('label', {}, 'Name ', name), el('label', {}, 'Format ', fmt), where, el('div', { class: 'buttons' }, go));
  const dlg = modal('Save the configuration', body);
  name.focus();
  name.select();
  const run = async () => {
    try {
      const r = await page.t.request<SaveResult>('save', { model: page.model.model, name: name.value, format: fmt.value });
      dlg.close();
      toast(el('div', { class: 'saved', 'data-path': r.path }, 'Saved to ', fileLink(r.path, r.relative), '.'), 'info');
    } catch (e) {
      toast(`Save: ${(e as Error).message}`, 'error');
    }
  };
  go.addEventListener('click', () => void run());
  name.addEventListener('keydown', (ev) => ev.key === 'Enter' && void run());
}

export async function loadDialog(page: Page): Promise<void> {
  let list: ConfigsJson;
  try {
    list = await page.t.request<ConfigsJson>('configs', { model: page.model.model });
  } catch (e) {
    toast(`Load: ${(e as Error).message}`, 'error');
    return;
  }
  const ul = el('ul', { class: 'config-files' });
  for (const f of list.files) {
    const b = el('button', { class: 'small', 'data-path': f.path }, 'Load');
    b.addEventListener('click', () => {
      dlg.close();
      void load(page, { path: f.path }, f.name);
    });
    ul.append(el('li', {}, b, ' ', el('code', {}, f.name), el('span', { class: 'muted' }, ` ${FORMAT_LABEL[f.format] ?? f.format}`)));
  }
  const file = el('input', { type: 'file', id: 'load-file', accept: '.json,.xml,.config' }) as HTMLInputElement;
  file.addEventListener('change', () => {
    const f = file.files?.[0];
    if (!f) return;
    if (f.size > 4 * 1024 * 1024) {
      toast(`${f.name} is larger than a configuration tvl-lsp reads (4 MB)`, 'error');
      return;
    }
    void f.text().then((text) => {
      dlg.close();
      void load(page, { text, filename: f.name }, f.name);
    });
  });
  const body = el('div', { class: 'form' },
    list.files.length ? el('p', {}, `Saved next to the model (${list.relative}):`) : el('p', { class: 'muted' },
      `No configuration next to the model (${list.relative}) yet: save one, or load a file.`),
    ul,
    el('label', {}, 'Or a file (tvl-lsp JSON, FeatureIDE XML or .config, uvls .uvl.json): ', file),
    el('p', { class: 'muted' }, 'Its decisions replace yours (Undo last brings yours back).'));
  const dlg = modal('Load a configuration', body);
}

async function load(page: Page, params: Record<string, unknown>, label: string): Promise<void> {
  const before = { ...page.state.decisions };
  page.busy(1);
  try {
    const r = await page.t.request<LoadResult>('load', { model: page.model.model, ...params, counts: page.wanted() });
    page.history.push(before);
    page.applyState(r.state);
    page.takeCounts(r.counts);
    const l = r.loaded;
    const parts = [`Loaded ${label}: ${l.decisions} decision${l.decisions === 1 ? '' : 's'}`];
    if (l.unknownCount) {
      parts.push(`${l.unknownCount} name${l.unknownCount === 1 ? '' : 's'} not in this model ignored (${l.unknown.slice(0, 5).join(', ')}${l.unknownCount > 5 ? ', …' : ''})`);
    }
    if (l.ignored.length) {
      parts.push(`${l.ignored.length} value${l.ignored.length === 1 ? '' : 's'} that are not a selection ignored`);
    }
    if (r.refused) {
      parts.push(`stopped at a conflict: ${r.refused.message}`);
    }
    toast(el('div', { class: 'loaded', 'data-decisions': String(l.decisions) }, parts.join('; ') + '.'), r.refused ? 'refusal' : 'info',
      Boolean(r.refused));
  } catch (e) {
    toast(`Load: ${(e as Error).message}`, 'error');
  } finally {
    page.busy(-1);
  }
}

export async function generate(page: Page, mode: string): Promise<void> {
  page.busy(1);
  try {
    const r = await page.t.request<GenerateResult>('generate', { model: page.model.model, mode });
    const files = r.written ?? r.files.map((f) => f.path);
    const ul = el('ul', { class: 'files' });
    files.slice(0, 12).forEach((f) => ul.append(el('li', { 'data-path': f }, fileLink(f, f.split('/').pop()))));
    if (files.length > 12) {
      ul.append(el('li', { class: 'muted' }, `… and ${files.length - 12} more in ${relative(r.folder)}`));
    }
    const head = files.length
      ? `Wrote ${files.length} configuration launch file${files.length > 1 ? 's' : ''} to ${relative(r.folder)}`
      : 'No product to write.';
    const out = el('div', { class: 'generated', 'data-count': String(files.length), 'data-cut': String(Boolean(r.cut)) }, head, ul);
    if (r.cut) {
      const setting = page.t.kind === 'vscode' ? 'the tvl-lsp generate.limit setting' : 'tvl-lsp ui --limit N';
      const total = r.available != null ? `${formatCount(String(r.available))} products` : 'more products';
      out.append(el('div', { class: 'limit', 'data-limit': String(r.limit) },
        `The limit of ${r.limit} files per Generate cut the rest: there are ${total}. Decide more features first, or raise it (${setting}).`));
    }
    toast(out, 'info', true);
  } catch (e) {
    toast(`Generate: ${(e as Error).message}`, 'error');
  } finally {
    page.busy(-1);
  }
}

/** In the graph panel when the model configures no launch file: choose one. */
export async function pairPanel(page: Page, box: HTMLElement): Promise<void> {
  let got: LaunchesJson;
  try {
    got = await page.t.request<LaunchesJson>('launches', { model: page.model.model });
  } catch (e) {
    box.replaceChildren(el('div', { class: 'empty' }, `No computation graph: ${(e as Error).message}`));
    return;
  }
  const n = page.index.size;
  const sel = el('select', { id: 'pair-launch', 'aria-label': 'launch file' }) as HTMLSelectElement;
  for (const c of got.candidates) {
    sel.append(el('option', { value: c.path }, `${c.relative} — ${c.matches} of ${n} features are its args`));
  }
  const use = el('button', { class: 'primary', id: 'pair-go' }, 'Configure it');
  use.addEventListener('click', () => void (async () => {
    try {
      await page.t.request('pair', { model: page.model.model, launch: sel.value });
      await page.reload();
    } catch (e) {
      toast(`Pair: ${(e as Error).message}`, 'error');
    }
  })());
  const help = 'tvl-lsp pairs a model with a launch file through a HAROS project file, a marker comment ' +
    '(<!-- tvl-lsp: model ... -->) or the same name (generic.tvl + generic.launch).';
  box.replaceChildren(el('div', { class: 'pair' },
    el('p', {}, el('strong', {}, 'This model configures no launch file'), ' — so there is no computation graph and nothing to generate.'),
    got.candidates.length
      ? el('div', {}, el('p', {}, 'Choose the launch file whose top-level args are the model\'s features:'), sel, ' ', use)
      : el('p', { class: 'muted' }, 'There is no launch file in this workspace.'),
    el('p', { class: 'muted' }, help)));
}
