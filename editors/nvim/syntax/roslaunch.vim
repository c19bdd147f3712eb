" ROS launch files are XML: XML highlighting plus $(arg ...), $(find ...) substitutions.
if exists('b:current_syntax')
  finish
endif
runtime! syntax/xml.vim
unlet! b:current_syntax
syn match roslaunchSubst /\$([a-z]\+\%(\s\+[^()$]*\)\=)/ contained containedin=xmlString,xmlTagName,xmlAttrib
hi def link roslaunchSubst PreProc
let b:current_syntax = 'roslaunch'
