# hookup_moveoff.tcl: puts the moveoff component between the motion
# controller and the joints' position loops, for INI files that name it
# as [HAL]HALFILE = LIB:hookup_moveoff.tcl after the files that connect
# joint.N.motor-pos-cmd and joint.N.motor-pos-fb.
#
# It loads moveoff as `mv` (personality: one more than the highest
# [JOINT_N] with a TYPE), adds mv.read-inputs just before
# motion-command-handler and mv.write-outputs just after
# motion-controller, and rewires each joint N:
#
#   joint.N.motor-pos-cmd --hu:pos-N--> mv.pos-N
#   mv.pos-plusoffset-N --hu:plus-N--> what read the commanded position
#   the feedback's writer --hu:fb-N--> mv.fb-N and the feedback's readers
#   mv.fb-minusoffset-N --hu:minus-N--> joint.N.motor-pos-fb
#
# A joint whose command is looped straight back to its feedback (one
# signal) gets hu:shortcircuit-N instead: mv.pos-plusoffset-N to mv.fb-N
# and the command's readers. The settings come from [MOVEOFF] (EPSILON,
# WAYPOINT_SAMPLE_SECS, WAYPOINT_THRESHOLD, BACKTRACK_ENABLE) and, per
# joint, [MOVEOFF_N] or else [JOINT_N] (MAX_VELOCITY, MAX_ACCELERATION,
# MAX_LIMIT, MIN_LIMIT); what neither gives keeps moveoff's default.
# Under [HAL]TWOPASS it does its work in pass 1, when the pins exist.

source [file join $::env(HALLIB_DIR) hal_procs_lib.tcl]

namespace eval ::moveoff_hookup {
  # The component's name, as moveoff_gui and moveoff_external.hal expect.
  variable comp mv
}

# The joints with a [JOINT_N] section that gives a TYPE, N 0 to 8.
proc ::moveoff_hookup::joints {} {
  set found {}
  for {set j 0} {$j < 9} {incr j} {
    if {[info exists ::JOINT_${j}(TYPE)]} {lappend found $j}
  }
  if {![llength $found]} {
    return -code error "no \[JOINT_N\] section with a TYPE: no joint to hook up"
  }
  return $found
}

# The last value of an INI item, or "" when the INI file lacks it.
proc ::moveoff_hookup::ini {section item} {
  set var ::${section}($item)
  if {[info exists $var]} {return [lindex [set $var] end]}
  return ""
}

# The signal a pin is on; an error when it is on none.
proc ::moveoff_hookup::signal_of {pin} {
  if {![connection_info info $pin]} {
    return -code error "pin $pin does not exist"
  }
  if {$info(signame) eq ""} {
    return -code error "$pin is on no signal: a HAL file before\
        hookup_moveoff.tcl must connect it"
  }
  return $info(signame)
}

# The pins a signal drives, less `except`, and the pin that drives it.
proc ::moveoff_hookup::readers {sig except} {
  get_netlist in out io $sig
  return [lsearch -all -inline -not -exact [concat $in $io] $except]
}
proc ::moveoff_hookup::writer {sig} {
  get_netlist in out io $sig
  return [lindex $out 0]
}

# Loads the component and puts its functions around motion's.
proc ::moveoff_hookup::load {joints} {
  variable comp
  set count [expr {[lindex $joints end] + 1}]
  hal loadrt moveoff personality=$count names=$comp
  set thread [thread_info threads]
  if {$thread eq ""} {
    return -code error "motion-controller is in no thread: load motion\
        and add its functions before hookup_moveoff.tcl"
  }
  # write-outputs right after motion-controller, then read-inputs where
  # motion-command-handler is now (it moves down one).
  set after [expr {$threads($thread,motion-controller) + 1}]
  hal addf $comp.write-outputs $thread $after
  hal addf $comp.read-inputs $thread $threads($thread,motion-command-handler)
}

# Rewires joint j's command and feedback through the component.
proc ::moveoff_hookup::rewire {j} {
  variable comp
  set cmd joint.$j.motor-pos-cmd
  set fb joint.$j.motor-pos-fb
  set cmd_sig [signal_of $cmd]
  set fb_sig [signal_of $fb]
  set cmd_readers [readers $cmd_sig $fb]
  if {$cmd_sig eq $fb_sig} {
    hal delsig $cmd_sig
    hal net hu:pos-$j $cmd $comp.pos-$j
    hal net hu:shortcircuit-$j $comp.pos-plusoffset-$j $comp.fb-$j {*}$cmd_readers
  } else {
    set fb_writer [writer $fb_sig]
    set fb_readers [readers $fb_sig $fb]
    hal delsig $cmd_sig
    hal delsig $fb_sig
    hal net hu:pos-$j $cmd $comp.pos-$j
    if {[llength $cmd_readers]} {
      hal net hu:plus-$j $comp.pos-plusoffset-$j {*}$cmd_readers
    }
    hal net hu:fb-$j {*}$fb_writer $comp.fb-$j {*}$fb_readers
  }
  hal net hu:minus-$j $comp.fb-minusoffset-$j $fb
}

# Joint j's limits: [MOVEOFF_j], else [JOINT_j] (said), else the default.
proc ::moveoff_hookup::joint_settings {j} {
  variable comp
  foreach {pin item} {offset-vel MAX_VELOCITY offset-accel MAX_ACCELERATION
                      offset-max MAX_LIMIT offset-min MIN_LIMIT} {
    set value [ini MOVEOFF_$j $item]
    if {$value eq ""} {
      set value [ini JOINT_$j $item]
      if {$value ne ""} {
        puts "hookup_moveoff.tcl: $comp.$pin-$j from \[JOINT_$j\]$item = $value"
      }
    }
    if {$value ne ""} {hal setp $comp.$pin-$j $value}
  }
}

# The component's own settings from [MOVEOFF].
proc ::moveoff_hookup::settings {} {
  variable comp
  foreach {pin item} {epsilon EPSILON waypoint-sample-secs WAYPOINT_SAMPLE_SECS
                      waypoint-threshold WAYPOINT_THRESHOLD
                      backtrack-enable BACKTRACK_ENABLE} {
    set value [ini MOVEOFF $item]
    if {$value ne ""} {hal setp $comp.$pin $value}
  }
}

proc ::moveoff_hookup::run {} {
  set joints [joints]
  load $joints
  foreach j $joints {
    rewire $j
    joint_settings $j
  }
  settings
}

if {[namespace exists ::tp] && [::tp::passnumber] == 0} {
  # TWOPASS: nothing exists yet in pass 0; all is done in pass 1.
  return
}
if {[catch {::moveoff_hookup::run} msg]} {
  return -code error "hookup_moveoff.tcl: $msg"
}
