# xhc-hb04.tcl: the XHC HB04 wireless USB pendant, as LinuxCNC's
# configurations name it ([HAL]HALFILE = LIB:xhc-hb04.tcl, settings in
# [XHC_HB04_CONFIG] and [XHC_HB04_BUTTONS], halui required).
#
# This suite has no driver for the pendant (LinuxCNC's xhc-hb04 user
# program). The settings are checked as LinuxCNC checks them, so a
# configuration with a mistake still stops with the mistake named; the
# machine then starts without the pendant, as LinuxCNC's does when the
# driver cannot start, and says so: no xhc-hb04.* or pendant_util.* pins
# are created, and nothing is connected to halui for it.

proc xhc_hb04_refuse {msg} {
  return -code error "xhc-hb04.tcl: $msg"
}

# An INI section as a Tcl array: is it there at all?
proc xhc_hb04_has_section {name} {
  return [expr {[array exists ::$name] && [array size ::$name] > 0}]
}

if {![info exists ::HAL(HALUI)]} {
  xhc_hb04_refuse "\[HAL\]HALUI is not set (the pendant works through halui)"
}
foreach section {XHC_HB04_CONFIG XHC_HB04_BUTTONS} {
  if {![xhc_hb04_has_section $section]} {
    xhc_hb04_refuse "the INI file has no \[$section\] section"
  }
}

# A setting of [XHC_HB04_CONFIG], in lower or upper case (lower wins, as
# in LinuxCNC), without the braces a list value may carry; "" if unset.
proc xhc_hb04_setting {name} {
  foreach key [list [string tolower $name] [string toupper $name]] {
    if {[info exists ::XHC_HB04_CONFIG($key)]} {
      return [string trim [lindex $::XHC_HB04_CONFIG($key) 0] "{}"]
    }
  }
  return ""
}

set xhc_hb04_coords [xhc_hb04_setting coords]
if {$xhc_hb04_coords ne ""} {
  if {[llength $xhc_hb04_coords] > 4} {
    xhc_hb04_refuse "\[XHC_HB04_CONFIG\]coords names more than 4 letters:\
      <$xhc_hb04_coords>"
  }
  if {[llength [lsort -unique $xhc_hb04_coords]] != [llength $xhc_hb04_coords]} {
    xhc_hb04_refuse "\[XHC_HB04_CONFIG\]coords must name each letter once:\
      <$xhc_hb04_coords>"
  }
  foreach letter $xhc_hb04_coords {
    if {[string first [string tolower $letter] xyzabcuvw] < 0} {
      xhc_hb04_refuse "\[XHC_HB04_CONFIG\]coords: '$letter' is not an axis letter"
    }
  }
}
set xhc_hb04_jogmode [xhc_hb04_setting jogmode]
if {$xhc_hb04_jogmode ni {"" normal vnormal}} {
  puts stderr "xhc-hb04.tcl: \[XHC_HB04_CONFIG\]jogmode '$xhc_hb04_jogmode'\
    is not normal or vnormal: normal is used"
}

puts stderr "xhc-hb04.tcl: this suite has no driver for the XHC HB04 pendant:\
  continuing without it (no xhc-hb04.* pins; its \[XHC_HB04_BUTTONS\] are\
  not connected)"
