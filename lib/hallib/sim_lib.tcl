# sim_lib.tcl: Tcl procedures that build simulated machines from the INI
# file's settings (used by basic_sim.tcl). Joint N's signals are named
# J<N>:..., components J<N>_pid, J<N>_mux, J<N>_vel, J<N>_accel,
# J<N>_switch, as in LinuxCNC's.

# Joint numbers of the axis letters for trivkins: consecutive joints in
# the order of the coordinates.
proc indices_for_trivkins {axes} {
  if {$axes eq ""} {set axes {x y z a b c u v w}}
  set joint 0
  foreach letter [string tolower $axes] {
    set ::SIM_LIB(jointidx,$letter) $joint
    incr joint
  }
}

# [TRAJ]COORDINATES, written "X Y Z" or "XYZ", as a list {x y z}.
proc get_traj_coordinates {} {
  set c [lindex $::TRAJ(COORDINATES) 0]
  set c [string map {" " "" "\t" ""} $c]
  return [string tolower [split $c ""]]
}

# The INI items a simulated machine needs.
proc check_ini_items {} {
  foreach {section item} {KINS KINEMATICS KINS JOINTS TRAJ COORDINATES} {
    if {![info exists ::${section}($item)]} {
      return -code error "Missing inifile item: \[$section\]$item"
    }
  }
  set kins [lindex $::KINS(KINEMATICS) 0]
  if {[info exists ::DISPLAY(LATHE)] && [lsearch $kins trivkins] >= 0
      && [string first "=" $kins] < 0} {
    return -code error "trivkins lathe config must specify coordinates= \
(typically use \[KINS\]KINEMATICS trivkins coordinates=XZ)"
  }
  foreach word [split $kins] {
    if {[string first coordinates= $word] != 0} continue
    set coords [lindex [split $word =] end]
    if {[string length $coords] != [lindex $::KINS(JOINTS) 0]} {
      puts stderr "check_ini_items: WARNING: trivkins coordinates=$coords\
 gives [string length $coords] joints but \[KINS\]JOINTS is $::KINS(JOINTS)"
    }
  }
}

# Loads the kinematics of [KINS]KINEMATICS (default trivkins).
proc setup_kins {axes} {
  if {![info exists ::KINS(KINEMATICS)]} {
    puts stderr "setup_kins: no \[KINS\]KINEMATICS, using trivkins"
    loadrt trivkins
    return
  }
  set kins [lindex $::KINS(KINEMATICS) end]
  eval loadrt $kins
  # Other modules (xyzac-trt-kins, scarakins...) number their joints in
  # the order of the coordinates as well.
  indices_for_trivkins $axes
  if {[lindex $kins 0] ne "trivkins"} {
    puts stderr "setup_kins: using [lindex $kins 0], joints in the order of the coordinates"
  }
}

# The machine core: kinematics, motion, and per joint a pass-through pid
# (FF0 = 1) feeding a mux2 that holds the position while motion is off,
# so feedback behaves as a servo machine's. E-stop and tool loops closed.
proc core_sim {axes number_of_joints servo_period {base_period 0} {emcmot motmod}} {
  setup_kins $axes
  set module [split [lindex $emcmot 0]]
  eval loadrt [lindex $module 0] [lrange $module 1 end] \
      base_period_nsec=$base_period \
      servo_period_nsec=$servo_period \
      num_joints=$number_of_joints
  addf motion-command-handler servo-thread
  addf motion-controller servo-thread

  set pids {}
  set muxes {}
  for {set j 0} {$j < $number_of_joints} {incr j} {
    lappend pids J${j}_pid
    lappend muxes J${j}_mux
  }
  loadrt pid names=[join $pids ,]
  loadrt mux2 names=[join $muxes ,]
  foreach p $pids {
    addf $p.do-pid-calcs servo-thread
    do_setp $p.FF0 1.0
    foreach gain {Pgain Dgain Igain FF1 FF2} {do_setp $p.$gain 0}
  }
  foreach m $muxes {
    addf $m servo-thread
  }

  net estop:loop <= iocontrol.0.user-enable-out
  net estop:loop => iocontrol.0.emc-enable-in
  net tool:prep-loop <= iocontrol.0.tool-prepare
  net tool:prep-loop => iocontrol.0.tool-prepared
  net tool:change-loop <= iocontrol.0.tool-change
  net tool:change-loop => iocontrol.0.tool-changed

  net sample:enable <= motion.motion-enabled
  for {set j 0} {$j < $number_of_joints} {incr j} {
    net sample:enable => J${j}_mux.sel
    net J${j}:enable <= joint.$j.amp-enable-out
    net J${j}:enable => J${j}_pid.enable
    net J${j}:pos-cmd <= joint.$j.motor-pos-cmd
    net J${j}:pos-cmd => J${j}_pid.command
    net J${j}:on-pos <= J${j}_pid.output
    net J${j}:on-pos => J${j}_mux.in1
    net J${j}:pos-fb <= J${j}_mux.out
    net J${j}:pos-fb => J${j}_mux.in0
    net J${j}:pos-fb => joint.$j.motor-pos-fb
  }
}

# Velocity and acceleration of each joint (ddt, at most 16), and the XY
# and XYZ speeds when X, Y and Z exist.
proc make_ddts {number_of_joints} {
  set names {}
  for {set j 0} {$j < $number_of_joints && [llength $names] < 16} {incr j} {
    lappend names J${j}_vel J${j}_accel
  }
  if {[llength $names] < 2 * $number_of_joints} {
    puts stderr "make_ddts: number of ddts limited to 16"
  }
  loadrt ddt names=[join $names ,]
  foreach n $names {addf $n servo-thread}
  for {set j 0} {2 * $j < [llength $names]} {incr j} {
    net J${j}:pos-fb => J${j}_vel.in
    net J${j}:vel <= J${j}_vel.out
    net J${j}:vel => J${j}_accel.in
    net J${j}:acc <= J${j}_accel.out
  }
  foreach letter {x y z} {
    if {![info exists ::SIM_LIB(jointidx,$letter)]} return
  }
  loadrt hypot names=hyp_xy,hyp_xyz
  addf hyp_xy servo-thread
  addf hyp_xyz servo-thread
  set x $::SIM_LIB(jointidx,x)
  set y $::SIM_LIB(jointidx,y)
  set z $::SIM_LIB(jointidx,z)
  net J$x:vel => hyp_xy.in0
  net J$x:vel => hyp_xyz.in0
  net J$y:vel => hyp_xy.in1
  net J$y:vel => hyp_xyz.in1
  net J$z:vel => hyp_xyz.in2
  net xy:vel => hyp_xy.out
  net xyz:vel <= hyp_xyz.out
}

# The manual tool change dialog in place of the tool change loopback.
proc use_hal_manualtoolchange {} {
  loadusr -W hal_manualtoolchange
  unlinkp iocontrol.0.tool-change
  unlinkp iocontrol.0.tool-changed
  delsig tool:change-loop
  net tool:change <= iocontrol.0.tool-change
  net tool:change => hal_manualtoolchange.change
  net tool:changed <= hal_manualtoolchange.changed
  net tool:changed => iocontrol.0.tool-changed
  net tool:prep-number <= hal_manualtoolchange.number
  net tool:prep-number => iocontrol.0.tool-prep-number
}

# A simulated home switch per joint (sim_home_switch).
proc simulated_home {number_of_joints} {
  set names {}
  for {set j 0} {$j < $number_of_joints} {incr j} {lappend names J${j}_switch}
  loadrt sim_home_switch names=[join $names ,]
  foreach n $names {addf $n servo-thread}
  for {set j 0} {$j < $number_of_joints} {incr j} {
    net J${j}:pos-fb => J${j}_switch.cur-pos
    net J${j}:homesw <= J${j}_switch.home-sw
    net J${j}:homesw => joint.$j.home-sw-in
    # inch machines: a switch travel scaled for inches
    if {[info exists ::JOINT_${j}(TYPE)]
        && [lindex [set ::JOINT_${j}(TYPE)] 0] ne "ANGULAR"
        && [info exists ::TRAJ(LINEAR_UNITS)]
        && [lsearch {in inch imperial} [lindex $::TRAJ(LINEAR_UNITS) 0]] >= 0} {
      do_setp J${j}_switch.hysteresis 0.05
      do_setp J${j}_switch.home-pos 0.10
    }
  }
}

# A simulated spindle with an encoder (as sim_spindle_encoder.hal).
proc sim_spindle {} {
  loadrt sim_spindle names=sim_spindle
  do_setp sim_spindle.scale 0.01666667
  loadrt limit2 names=limit_speed
  loadrt lowpass names=spindle_mass
  loadrt near names=near_speed
  do_setp limit_speed.maxv 5000.0
  net spindle-index-enable <=> spindle.0.index-enable
  net spindle-index-enable <=> sim_spindle.index-enable
  net spindle-pos <= sim_spindle.position-fb
  net spindle-pos => spindle.0.revs
  do_setp spindle_mass.gain .07
  net spindle-speed-cmd <= spindle.0.speed-out
  net spindle-speed-cmd => limit_speed.in
  net spindle-speed-cmd => near_speed.in1
  net spindle-speed-limited <= limit_speed.out
  net spindle-speed-limited => sim_spindle.velocity-cmd
  net spindle-speed-limited => spindle_mass.in
  net spindle-rpm-filtered <= spindle_mass.out
  net spindle-rpm-filtered => spindle.0.speed-in
  net spindle-rpm-filtered => near_speed.in2
  do_setp near_speed.scale 1.1
  do_setp near_speed.difference 10
  net spindle-at-speed <= near_speed.out
  net spindle-at-speed => spindle.0.at-speed
  addf limit_speed servo-thread
  addf spindle_mass servo-thread
  addf near_speed servo-thread
  addf sim_spindle servo-thread
}

# setp, remembered for save_hal_cmds.
proc do_setp {pname value} {
  setp $pname $value
  lappend ::SIM_LIB(setp_list) $pname $value
}

# Writes the HAL commands made so far (hal save all) and the remembered
# setp commands to savefilename.
proc save_hal_cmds {savefilename {options ""}} {
  set fd [open $savefilename w]
  puts $fd "# HAL commands made by [file tail [info script]] ([clock format [clock seconds]])"
  if {[lsearch $options use_hal_manualtoolchange] >= 0} {
    puts $fd "loadusr -W hal_manualtoolchange"
  }
  puts $fd [hal save all]
  if {[info exists ::SIM_LIB(setp_list)]} {
    puts $fd "# setp commands for unconnected input pins"
    foreach {pname value} $::SIM_LIB(setp_list) {
      puts $fd "setp $pname $value"
    }
  }
  close $fd
}
