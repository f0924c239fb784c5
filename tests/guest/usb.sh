# The USB suite, run by the guest's init (tests/guest/init) as root in a kernel with dummy_hcd
# and FunctionFS: makes a configfs gadget with one FunctionFS function, starts the glove on it
# (ffs_glove writes the descriptors and then sends frames on interface 0, and logs the haptic
# frames it reads on interface 1 to $HAPTIC_LOG), binds the gadget to dummy_hcd's controller,
# so the same kernel enumerates it as a USB device, and runs the libusb tests.
set -e
mount -t configfs configfs /sys/kernel/config
G=/sys/kernel/config/usb_gadget/glove
mkdir "$G"
echo 0x1209 >"$G/idVendor" # pid.codes' test ids
echo 0x0001 >"$G/idProduct"
mkdir "$G/strings/0x409"
echo sculpt >"$G/strings/0x409/manufacturer"
echo "sculpt FunctionFS glove" >"$G/strings/0x409/product"
mkdir "$G/configs/c.1" "$G/functions/ffs.glove"
ln -s "$G/functions/ffs.glove" "$G/configs/c.1/"
mkdir -p /dev/ffs-glove
mount -t functionfs glove /dev/ffs-glove
HAPTIC_LOG=/tmp/haptic-frames.log
/opt/sculpt/ffs_glove /dev/ffs-glove "$HAPTIC_LOG" &
i=0
while [ ! -e /dev/ffs-glove/ep2 ]; do
  i=$((i + 1))
  [ "$i" -lt 100 ] || { echo "usb.sh: ffs_glove did not come up"; exit 1; }
  sleep 0.1
done
UDC=$(ls /sys/class/udc | head -n 1)
echo "$UDC" >"$G/UDC"
echo "usb.sh: gadget bound to $UDC"
GLOVE_GADGET=$G GLOVE_UDC=$UDC GLOVE_HAPTIC_LOG=$HAPTIC_LOG GTEST_COLOR=no /opt/sculpt/guest_usb_tests
