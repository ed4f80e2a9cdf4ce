# xhc-hb04.tcl: the XHC HB04 wireless USB pendant, as LinuxCNC's
# configurations name it ([HAL]HALFILE = LIB:xhc-hb04.tcl, settings in
# [XHC_HB04_CONFIG] and [XHC_HB04_BUTTONS], halui required).
#
# Starts the xhc-hb04 driver (-x unless require_pendant = no, -s from
# sequence, -I the layout's button file), loads xhc_hb04_util as
# pendant_util, and connects: each [XHC_HB04_BUTTONS] name = pin to the
# button's pin (start-pause = std_start_pause for halui's run, pause and
# resume), and per coordinate in coords the wheel (through pendant_util's
# filter and scale), the jog scale, the enable and the displayed
# positions, to axis.L.* and, where the coordinate has one joint, to
# joint.N.*. The wheel also drives halui's feed and spindle overrides.
# When the button file or the driver cannot be had, the machine starts
# without the pendant and says so, as LinuxCNC does.

source [file join $::env(HALLIB_DIR) hal_procs_lib.tcl]

proc xhc_hb04_refuse {msg} {
  return -code error "xhc-hb04.tcl: $msg"
}

proc xhc_hb04_note {msg} {
  puts stderr "xhc-hb04.tcl: $msg"
}

# An INI section as a Tcl array: is it there at all?
proc xhc_hb04_has_section {name} {
  return [expr {[array exists ::$name] && [array size ::$name] > 0}]
}

# A setting of an INI section, in lower or upper case (lower wins, as in
# LinuxCNC), without the braces a list value may carry; def if unset.
proc xhc_hb04_get {section name {def ""}} {
  foreach key [list [string tolower $name] [string toupper $name] $name] {
    if {[info exists ::${section}($key)]} {
      return [string trim [lindex [set ::${section}($key)] 0] "{}"]
    }
  }
  return $def
}

# `net` that remembers a failure and goes on; the failures are listed
# at the end.
proc xhc_hb04_net {args} {
  if {[catch {eval net $args} msg]} {
    lappend ::xhc_hb04_failed "[lindex $args 0]: $msg"
  }
}

# The signal already driven by an output pin, or the name given.
proc xhc_hb04_signal_of {pin name} {
  if {[is_connected $pin sig] eq "is_output"} {return $sig}
  return $name
}

# The joint of a coordinate letter under trivkins-style identity
# kinematics: its place in [KINS]KINEMATICS coordinates= (or
# [TRAJ]COORDINATES), when it is there exactly once; -1 otherwise.
proc xhc_hb04_joint_of {letter} {
  set coords ""
  if {[info exists ::KINS(KINEMATICS)]} {
    regexp -nocase {coordinates=([a-z]+)} [lindex $::KINS(KINEMATICS) 0] -> coords
  }
  if {$coords eq "" && [info exists ::TRAJ(COORDINATES)]} {
    set coords [join [lindex $::TRAJ(COORDINATES) 0] ""]
  }
  set coords [string tolower [string map {" " ""} $coords]]
  set found [lsearch -all [split $coords ""] [string tolower $letter]]
  if {[llength $found] == 1} {return [lindex $found 0]}
  return -1
}

# A list setting of numbers, four entries, def where missing.
proc xhc_hb04_numbers {name def} {
  set out [list $def $def $def $def]
  set i 0
  foreach v [xhc_hb04_get XHC_HB04_CONFIG $name] {
    if {$i > 3} break
    if {![string is double -strict $v]} {
      xhc_hb04_refuse "\[XHC_HB04_CONFIG\]$name: '$v' is not a number"
    }
    lset out $i $v
    incr i
  }
  return $out
}

# --- settings ---------------------------------------------------------
if {![info exists ::HAL(HALUI)]} {
  xhc_hb04_refuse "\[HAL\]HALUI is not set (the pendant works through halui)"
}
foreach section {XHC_HB04_CONFIG XHC_HB04_BUTTONS} {
  if {![xhc_hb04_has_section $section]} {
    xhc_hb04_refuse "the INI file has no \[$section\] section"
  }
}
set ::xhc_hb04_failed {}
set xhc_hb04_pass0 [expr {[namespace exists ::tp] && [::tp::passnumber] == 0}]

set xhc_hb04_coords [string tolower \
  [string trim [lindex [array get ::XHC_HB04_CONFIG coords] 1] "{}"]]
if {$xhc_hb04_coords eq ""} {
  set xhc_hb04_coords [string tolower [xhc_hb04_get XHC_HB04_CONFIG coords "x y z a"]]
}
if {[llength $xhc_hb04_coords] > 4} {
  xhc_hb04_refuse "\[XHC_HB04_CONFIG\]coords names more than 4 letters:\
    <$xhc_hb04_coords>"
}
if {[llength [lsort -unique $xhc_hb04_coords]] != [llength $xhc_hb04_coords]} {
  xhc_hb04_refuse "\[XHC_HB04_CONFIG\]coords must name each letter once:\
    <$xhc_hb04_coords>"
}
foreach letter $xhc_hb04_coords {
  if {[string length $letter] != 1 || [string first $letter xyzabcuvw] < 0} {
    xhc_hb04_refuse "\[XHC_HB04_CONFIG\]coords: '$letter' is not an axis letter"
  }
}
set xhc_hb04_jogmode [xhc_hb04_get XHC_HB04_CONFIG jogmode normal]
if {$xhc_hb04_jogmode ni {normal vnormal}} {
  xhc_hb04_note "\[XHC_HB04_CONFIG\]jogmode '$xhc_hb04_jogmode'\
    is not normal or vnormal: normal is used"
  set xhc_hb04_jogmode normal
}
set xhc_hb04_coefs [xhc_hb04_numbers coefs 1.0]
set xhc_hb04_scales [xhc_hb04_numbers scales 1.0]
set xhc_hb04_accels {}
if {[xhc_hb04_get XHC_HB04_CONFIG mpg_accels] ne ""} {
  set xhc_hb04_accels [xhc_hb04_numbers mpg_accels 0.0]
}
for {set i 0} {$i < 4} {incr i} {
  set c [expr {abs([lindex $xhc_hb04_coefs $i])}]
  if {$c > 1} {
    xhc_hb04_note "\[XHC_HB04_CONFIG\]coefs entry $i is $c, more than 1: 0.5 is used"
    set c 0.5
  }
  lset xhc_hb04_coefs $i $c
}

set xhc_hb04_layout [xhc_hb04_get XHC_HB04_CONFIG layout 2]
switch -- $xhc_hb04_layout {
  1 {set xhc_hb04_cfg LIB:xhc-hb04-layout1.cfg}
  2 {set xhc_hb04_cfg LIB:xhc-hb04-layout2.cfg}
  default {
    xhc_hb04_note "layout '$xhc_hb04_layout' is not 1 or 2: trying it as a file"
    set xhc_hb04_cfg $xhc_hb04_layout
  }
}
set xhc_hb04_ini .
if {[info exists ::env(INI_FILE_NAME)]} {set xhc_hb04_ini $::env(INI_FILE_NAME)}
if {[catch {find_file_in_hallib_path $xhc_hb04_cfg $xhc_hb04_ini} xhc_hb04_path]} {
  xhc_hb04_note "no button file <$xhc_hb04_cfg>: continuing without the pendant"
  return
}

# --- the driver and its helper ----------------------------------------
set xhc_hb04_opts {}
if {[string tolower [xhc_hb04_get XHC_HB04_CONFIG require_pendant yes]] ne "no"} {
  lappend xhc_hb04_opts -x
}
set xhc_hb04_seq [xhc_hb04_get XHC_HB04_CONFIG sequence]
if {$xhc_hb04_seq ne ""} {lappend xhc_hb04_opts -s $xhc_hb04_seq}
if {[catch {eval loadusr -W xhc-hb04 $xhc_hb04_opts -I [list $xhc_hb04_path] -H} msg]} {
  xhc_hb04_note "loadusr xhc-hb04 $xhc_hb04_opts failed: $msg\n\
    Is the pendant plugged in, may this user open it?\
    Continuing without the pendant."
  return
}
if {[string match in* [xhc_hb04_get XHC_HB04_CONFIG inch_or_mm mm]]} {
  setp xhc-hb04.inch-icon 1
}
loadrt xhc_hb04_util names=pendant_util
addf pendant_util [xhc_hb04_get XHC_HB04_CONFIG threadname servo-thread]

# In twopass's first pass nothing is loaded yet: connections wait.
if {$xhc_hb04_pass0} {return}

# --- buttons ----------------------------------------------------------
proc xhc_hb04_start_pause {} {
  xhc_hb04_net pendant:start-or-pause <= xhc-hb04.button-start-pause \
    => pendant_util.start-or-pause
  xhc_hb04_net pendant:program-resume <= pendant_util.resume => halui.program.resume
  xhc_hb04_net pendant:program-pause <= pendant_util.pause => halui.program.pause
  xhc_hb04_net pendant:program-run <= pendant_util.run => halui.program.run \
    => halui.mode.auto
  foreach s {idle paused running} {
    xhc_hb04_net [xhc_hb04_signal_of halui.program.is-$s pendant:is-$s] \
      <= halui.program.is-$s => pendant_util.is-$s
  }
}

foreach name [lsort [array names ::XHC_HB04_BUTTONS]] {
  set target [lindex $::XHC_HB04_BUTTONS($name) 0]
  set lname [string tolower $name]
  if {$lname ne $name && [info exists ::XHC_HB04_BUTTONS($lname)]} continue
  if {$target eq "\"\"" || $target eq ""} continue
  if {$lname eq "start-pause" && [string tolower $target] eq "std_start_pause"} {
    xhc_hb04_start_pause
    continue
  }
  if {[string tolower $target] eq "caution"} {
    xhc_hb04_note "button $name is marked caution: not connected"
    continue
  }
  if {![pin_exists xhc-hb04.button-$lname]} {
    xhc_hb04_note "no pin xhc-hb04.button-$lname for \[XHC_HB04_BUTTONS\]$name"
    continue
  }
  if {![pin_exists $target]} {
    xhc_hb04_note "\[XHC_HB04_BUTTONS\]$name: no pin <$target>"
    continue
  }
  xhc_hb04_net pendant:$lname <= xhc-hb04.button-$lname => $target
}

# --- the wheel --------------------------------------------------------
# pendant_util divides the jog scale by k and multiplies the counts by
# k * scale, so that fractional scales work on the s32 counts.
set xhc_hb04_k 100.0
setp pendant_util.k $xhc_hb04_k
xhc_hb04_net pendant:jog-prescale <= xhc-hb04.jog.scale => pendant_util.divide-by-k-in
xhc_hb04_net pendant:jog-scale <= pendant_util.divide-by-k-out
xhc_hb04_net pendant:wheel-counts <= xhc-hb04.jog.counts
xhc_hb04_net pendant:wheel-counts-neg <= xhc-hb04.jog.counts-neg

# The pendant's four positions are labelled x y z a: a coordinate with
# one of those letters takes its own, the others the free ones in order.
set xhc_hb04_free {x y z a}
foreach c $xhc_hb04_coords {
  set i [lsearch $xhc_hb04_free $c]
  if {$i >= 0} {
    set xhc_hb04_slot($c) $c
    set xhc_hb04_free [lreplace $xhc_hb04_free $i $i]
  }
}
foreach c $xhc_hb04_coords {
  if {![info exists xhc_hb04_slot($c)]} {
    set xhc_hb04_slot($c) [lindex $xhc_hb04_free 0]
    set xhc_hb04_free [lrange $xhc_hb04_free 1 end]
    xhc_hb04_note "coordinate $c is on the pendant's $xhc_hb04_slot($c) position"
  }
}

foreach c $xhc_hb04_coords {
  set p $xhc_hb04_slot($c)
  set idx [lsearch {x y z a} $p]
  set C [string toupper $c]
  setp pendant_util.coef$idx [lindex $xhc_hb04_coefs $idx]
  setp pendant_util.scale$idx [expr {$xhc_hb04_k * [lindex $xhc_hb04_scales $idx]}]
  xhc_hb04_net [xhc_hb04_signal_of halui.axis.$c.pos-feedback pendant:pos-$c] \
    <= halui.axis.$c.pos-feedback => xhc-hb04.$p.pos-absolute
  xhc_hb04_net [xhc_hb04_signal_of halui.axis.$c.pos-relative pendant:pos-rel-$c] \
    <= halui.axis.$c.pos-relative => xhc-hb04.$p.pos-relative
  xhc_hb04_net pendant:jog-scale => axis.$c.jog-scale
  xhc_hb04_net pendant:wheel-counts => pendant_util.in$idx
  xhc_hb04_net pendant:wheel-counts-$c-filtered <= pendant_util.out$idx \
    => axis.$c.jog-counts
  xhc_hb04_net pendant:jog-$c <= xhc-hb04.jog.enable-$p => axis.$c.jog-enable
  if {$xhc_hb04_jogmode eq "vnormal"} {setp axis.$c.jog-vel-mode 1}
  set fraction 1.0
  if {$xhc_hb04_accels ne ""} {
    if {![info exists ::AXIS_${C}(MAX_ACCELERATION)]} {
      xhc_hb04_refuse "mpg_accels needs \[AXIS_$C\]MAX_ACCELERATION"
    }
    set fraction [expr {double([lindex $xhc_hb04_accels $idx]) \
      / [lindex [set ::AXIS_${C}(MAX_ACCELERATION)] 0]}]
  }
  setp axis.$c.jog-accel-fraction $fraction

  set j [xhc_hb04_joint_of $c]
  if {$j < 0} {
    xhc_hb04_note "coordinate $c has no single joint: only axis.$c is jogged"
    continue
  }
  if {![pin_exists joint.$j.jog-scale]} {
    xhc_hb04_refuse "coords = $xhc_hb04_coords: there is no joint.$j.jog-scale"
  }
  xhc_hb04_net pendant:jog-scale => joint.$j.jog-scale
  xhc_hb04_net pendant:wheel-counts-$c-filtered => joint.$j.jog-counts
  xhc_hb04_net pendant:jog-$c => joint.$j.jog-enable
  if {$xhc_hb04_jogmode eq "vnormal"} {setp joint.$j.jog-vel-mode 1}
  set fraction 1.0
  if {$xhc_hb04_accels ne ""} {
    if {![info exists ::JOINT_${j}(MAX_ACCELERATION)]} {
      xhc_hb04_refuse "mpg_accels needs \[JOINT_$j\]MAX_ACCELERATION"
    }
    set fraction [expr {double([lindex $xhc_hb04_accels $idx]) \
      / [lindex [set ::JOINT_${j}(MAX_ACCELERATION)] 0]}]
  }
  setp joint.$j.jog-accel-fraction $fraction
}

# The overrides and the display's speeds.
setp halui.feed-override.scale 0.01
xhc_hb04_net pendant:wheel-counts => halui.feed-override.counts
setp halui.spindle.0.override.scale 0.01
xhc_hb04_net pendant:wheel-counts => halui.spindle.0.override.counts
xhc_hb04_net pendant:feed-override-enable <= xhc-hb04.jog.enable-feed-override \
  => halui.feed-override.count-enable
xhc_hb04_net pendant:spindle-override-enable <= xhc-hb04.jog.enable-spindle-override \
  => halui.spindle.0.override.count-enable
xhc_hb04_net [xhc_hb04_signal_of motion.current-vel pendant:feed-value] \
  <= motion.current-vel => xhc-hb04.feed-value
xhc_hb04_net [xhc_hb04_signal_of spindle.0.speed-out-rps-abs pendant:spindle-rps] \
  <= spindle.0.speed-out-rps-abs => xhc-hb04.spindle-rps
xhc_hb04_net [xhc_hb04_signal_of halui.max-velocity.value pendant:jog-speed] \
  <= halui.max-velocity.value => xhc-hb04.jog.max-velocity
xhc_hb04_net [xhc_hb04_signal_of halui.feed-override.value pendant:feed-override] \
  <= halui.feed-override.value => xhc-hb04.feed-override
xhc_hb04_net [xhc_hb04_signal_of halui.spindle.0.override.value pendant:spindle-override] \
  <= halui.spindle.0.override.value => xhc-hb04.spindle-override

if {[llength $::xhc_hb04_failed]} {
  xhc_hb04_note "some pendant connections could not be made:\n  [join $::xhc_hb04_failed "\n  "]"
}
