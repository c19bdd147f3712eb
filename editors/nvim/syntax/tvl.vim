" Vim syntax file for TVL feature models (tvl-lsp). Semantic tokens from the server refine it.
if exists('b:current_syntax')
  finish
endif

syn case match
syn keyword tvlRoot        root nextgroup=tvlFeatureName skipwhite
syn match   tvlFeatureName /\h\w*/ contained
syn keyword tvlGroup       group
syn case ignore
syn keyword tvlDecomp      allOf oneOf someOf
syn match   tvlCondition   /\<if\(in\|out\)\s*:/
syn keyword tvlSelf        selectedChildren
syn case match
syn keyword tvlModifier    opt shared const constant
syn keyword tvlType        int real bool enum struct
syn keyword tvlOperatorW   is in requires excludes
syn keyword tvlInclude     include
syn keyword tvlSelf        this parent children
syn keyword tvlBoolean     true false
syn keyword tvlFunction    sum mul min max abs avg count and or xor not
syn match   tvlNumber      /\<\d\+\(\.\d\+\)\=\([eE][+-]\=\d\+\)\=\>/
syn match   tvlOperator    /<->\|->\|<-\|&&\|||\|==\|!=\|<=\|>=\|[!<>+\-*\/?:]/
syn match   tvlCardinality /\[\s*\(\d\+\|\*\)\s*\.\.\s*\(\d\+\|\*\)\s*\]/
syn region  tvlString      start=/"/ skip=/\\"/ end=/"/ oneline
syn keyword tvlTodo        TODO FIXME XXX contained
syn match   tvlLineComment /\/\/.*$/ contains=tvlTodo,@Spell
syn region  tvlBlockComment start=/\/\*/ end=/\*\// contains=tvlTodo,@Spell

hi def link tvlRoot         Keyword
hi def link tvlFeatureName  Type
hi def link tvlGroup        Keyword
hi def link tvlDecomp       Keyword
hi def link tvlCondition    Conditional
hi def link tvlModifier     StorageClass
hi def link tvlType         Type
hi def link tvlOperatorW    Operator
hi def link tvlInclude      Include
hi def link tvlSelf         Identifier
hi def link tvlBoolean      Boolean
hi def link tvlFunction     Function
hi def link tvlNumber       Number
hi def link tvlOperator     Operator
hi def link tvlCardinality  Number
hi def link tvlString       String
hi def link tvlTodo         Todo
hi def link tvlLineComment  Comment
hi def link tvlBlockComment Comment

let b:current_syntax = 'tvl'
