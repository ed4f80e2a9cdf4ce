# hal_procs_lib.tcl: Tcl procedures that look at the running HAL (pins,
# their connections, threads, signals) and find HAL files.
package require Hal

# 1 if the pin exists.
proc pin_exists {name} {
  return [expr {[lindex [hal list pin $name] 0] eq $name}]
}

# The fields of `show pin` for one pin, in the array result_name:
# owner type direction value separator signame. 0 if there is no pin.
proc connection_info {result_name pinname} {
  upvar $result_name info
  set row [lindex [split [hal show pin $pinname] \n] 2]
  set sep ""
  set sig ""
  if {[scan $row "%s %s %s %s %s %s %s" owner type dir val name sep sig] < 5} {
    return 0
  }
  array set info [list owner $owner type $type direction $dir value $val \
                       separator $sep signame $sig]
  return 1
}

# is_input, is_output, is_io or not_connected; the signal in signame.
proc is_connected {pinname {signame {}}} {
  upvar $signame sig
  set sig ""
  if {![connection_info info $pinname]} {return not_connected}
  set sig $info(signame)
  switch -- $info(separator) {
    "<==" {return is_input}
    "==>" {return is_output}
    "<=>" {return is_io}
  }
  return not_connected
}

# Threads and their functions, from `show thread`, in the array ay_name:
# (threadnames), (THREAD,period), (THREAD,fp), (THREAD,FUNCT) index,
# (THREAD,index,last), and for motion-command-handler and
# motion-controller their (NAME,threadname) and (NAME,index). Returns the
# thread of motion-controller.
proc thread_info {ay_name} {
  upvar $ay_name ay
  set lines [lrange [split [hal show thread] \n] 2 end-1]
  foreach line $lines {
    set f [regexp -all -inline {\S+} $line]
    if {[llength $f] == 0} continue
    if {[string is integer [lindex $f 0]] && [llength $f] == 2} {
      lassign $f index funct
      set ay($thread,$funct) $index
      set ay($thread,index,last) $index
      if {$funct in {motion-command-handler motion-controller}} {
        set ay($funct,threadname) $thread
        set ay($funct,index) $index
      }
    } elseif {[llength $f] >= 3} {
      lassign $f period fp thread
      lappend ay(threadnames) $thread
      set ay($thread,period) $period
      set ay($thread,fp) $fp
    }
  }
  if {[info exists ay(motion-controller,threadname)]} {
    if {![info exists ay(motion-command-handler,threadname)]} {
      return -code error "thread_info: motion-command-handler not found"
    }
    if {$ay(motion-controller,threadname) ne $ay(motion-command-handler,threadname)} {
      return -code error "thread_info: mot funcs on separate threads"
    }
    return $ay(motion-controller,threadname)
  }
}

# The pins of a signal: inputs, the output and I/O pins.
proc get_netlist {inpins_name outpin_name iopins_name signame} {
  upvar $inpins_name inpins $outpin_name outpin $iopins_name iopins
  set inpins {}
  set outpin {}
  set iopins {}
  foreach line [lrange [split [hal show signal $signame] \n] 2 end] {
    set f [regexp -all -inline {\S+} $line]
    switch -- [lindex $f 0] {
      "==>" {lappend inpins [lindex $f 1]}
      "<==" {lappend outpin [lindex $f 1]}
      "<=>" {lappend iopins [lindex $f 1]}
    }
  }
}

# A HAL file: LIB:NAME in $HALLIB_DIR; an absolute name as is; else
# beside the INI file, else in $HALLIB_DIR.
proc find_file_in_hallib_path {filename {inifile .}} {
  set name [lindex $filename end]
  if {[string first LIB: $name] == 0} {
    set path [file join $::env(HALLIB_DIR) [string range $name 4 end]]
  } elseif {[file pathtype $name] eq "absolute"} {
    set path $name
  } else {
    set path [file join [file dirname $inifile] $name]
    if {![file readable $path]} {
      set path [file join $::env(HALLIB_DIR) $name]
    }
  }
  if {[file readable $path]} {return $path}
  return -code error "find_file_in_hallib_path: cannot find: <$filename>"
}
