// What the page's parts (details, lists, actions) need of the page: its state and its verbs.
import type { FeatureIndex } from './model';
import type { Transport } from './transport';
import type { Counts, Explanation, GraphElement, GraphJson, ModelJson, Problem, State, Status } from './types';

export interface Selection {
  kind: 'feature' | 'element' | 'edge';
  id: string;
}

export interface Page {
  readonly t: Transport;
  model: ModelJson;
  index: FeatureIndex;
  state: State;
  counts: Counts | null;
  graphJson: GraphJson | null;
  graphStatus: Record<string, Status>;
  selection: Selection | null;
  problems: Problem[] | null;
  problemStatus: Record<string, Status>;
  showRuledOut: boolean;
  showAllProblems: boolean;
  /** decision sets before each change (Undo last) */
  history: Record<string, boolean>[];
  decide(feature: string, value: boolean | null): Promise<void>;
  /** replace every decision (undo, a loaded configuration); false when refused */
  setDecisions(decisions: Record<string, boolean>, what: string): Promise<boolean>;
  explain(feature: string): Promise<Explanation | null>;
  revealFeature(id: string): void;
  selectGraph(id: string): void;
  graphLinksOf(feature: string): GraphElement[];
  /** why a feature shows no count (compiling, not counted...) */
  countNote(): string;
  reload(): Promise<void>;
  refreshCounts(): Promise<void>;
  /** counts that came with an answer (or ask for them) */
  takeCounts(c: Counts | undefined): void;
  /** the features whose counts the page shows */
  wanted(): string[];
  applyState(state: State): void;
  busy(delta: number): void;
}
