# util_lib.tcl: procedures that show what a Tcl HAL file was given.
#   show_context  the script's arguments and INI file
#   show_ini      every INI section, as the arrays haltcl made of it
#   show_env      the environment
# In TWOPASS's first pass (::tp::passnumber 0) show_context and show_ini
# stay quiet, so each shows once.

set ::util_lib_quiet 0
if {[namespace exists ::tp] && [::tp::passnumber] == 0} {
  set ::util_lib_quiet 1
}

proc show_context {} {
  if {$::util_lib_quiet} return
  puts "show_context: argv0=$::argv0"
  puts "show_context:  argv=$::argv"
  foreach arg $::argv {
    puts "show_context:   arg=$arg"
  }
  if {[info exists ::env(INI_FILE_NAME)]} {
    puts "show_context: INI_FILE_NAME=$::env(INI_FILE_NAME)"
  }
}

proc show_ini {} {
  if {$::util_lib_quiet} return
  foreach v [lsort [uplevel #0 {info vars}]] {
    if {$v in {TP auto_index tcl_platform env}} continue
    if {[array exists ::$v]} {
      parray ::$v
    }
  }
}

proc show_env {} {
  parray ::env
}
