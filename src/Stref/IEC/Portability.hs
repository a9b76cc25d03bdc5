-- | Portability warnings for the IEC dialects: the constructs of a checked
-- program whose meaning a policy decides (docs/policies.md), found by
-- walking every user POU's statements. The analysis is syntactic and errs
-- on the side of saying too much: @x := x + 1@ is reported because it
-- overflows after enough cycles, whatever the program's inputs are.
module Stref.IEC.Portability (portability) where

import Data.List (nub, sortOn)
import Data.Map.Strict (Map)
import qualified Data.Map.Strict as M
import Data.Maybe (mapMaybe)
import Data.Text (Text)
import qualified Data.Text as T
import Stref.IEC.Checked
import Stref.IEC.Conversions (isConversionName)
import Stref.IEC.Syntax (BinOp (..), Pos (..), Section (..), binOpSymbol)
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Stref.Portability

-- | The warnings of a program, in source order.
portability :: Policies -> Program -> [Warning]
portability pol prog =
  nub . sortOn (\w -> (posLine (wPos w), posCol (wPos w))) $
    concat [block [] ss | d <- userPous, Statements ss <- [pdBody d]]
      ++ concatMap instanceWarnings userPous
      ++ concatMap shadowing userPous
  where
    -- TC-VAR-33: a local named like a global
    shadowing d =
      [ Warning (viPos v) ["name-resolution"] ["TC-VAR-33", "MT-SCOPE-5"] (viName v <> " is also the name of a global: which one it names here depends on the dialect")
      | v <- pdVars d
      , viSection v `notElem` [SecExternal, SecGlobal]
      , any ((== viKey v) . viKey) (prGlobals prog)
      ]
    names = declaredNames prog
    userPous = concatMap (\d -> d : M.elems (pdMethods d)) [d | d <- M.elems (prPous prog), isUser d]
    isUser d = case pdBody d of
      Statements _ -> True
      Native _ -> False

    -- the standard FBs whose outputs a policy decides
    instanceWarnings d =
      [ Warning (viPos v) [policy] rules (viName v <> " is a " <> fb <> ": " <> what)
      | v <- pdVars d
      , TFB fb <- [viType v]
      , (policy, rules, what) <- fbPolicies fb
      ]
    fbPolicies fb = case key fb of
      "F_TRIG" -> [("f-trig-initial", ["TC-FB-15", "NX-FB-10"], "whether its first call with CLK FALSE gives Q TRUE depends on its memory's initial value")]
      "CTD" -> [downQ]
      "CTUD" -> [downQ]
      "TON" -> [timerQ]
      "TOF" -> [timerQ]
      "TP" -> [timerQ]
      _ -> []
    downQ = ("down-counter-q", ["TC-FB-19", "TC-FB-24", "NX-FB-15"], "whether Q is TRUE when CV is below zero depends on the dialect")
    timerQ = ("timer-q", ["TC-FB-27", "NX-FB-26"], "the cycle in which Q switches when ET reaches PT depends on the dialect")

    -- statements, with the control variables of the FOR loops around them
    block loops = concatMap (stmt loops)
    stmt loops = \case
      CAssign p r t e -> accumulates p r t e ++ stored p t e ++ expr loops e ++ ref loops r
      CCallFB _ c -> concatMap (expr loops . snd) (fcInputs c) ++ ref loops (fcInstance c)
      CEval _ e -> expr loops e
      CIf _ arms els -> concat [expr loops c ++ block loops b | (c, b) <- arms] ++ block loops els
      CCase _ sel arms els -> expr loops sel ++ concatMap (block loops . snd) arms ++ block loops els
      CFor p r t s e st body -> forLoop p t e st body ++ concatMap (expr loops) (s : e : maybe [] pure st) ++ block (r : loops) body
      CWhile _ c body -> expr loops c ++ block loops body
      CRepeat _ body c -> block loops body ++ expr loops c
      CChain _ e targets -> expr loops e ++ concat [ref loops r | (_, r, _, _) <- targets]
      _ -> []

    -- x := x + c: the accumulator leaves its type after enough cycles
    accumulates p r t e = case (baseElem t, ceNode e) of
      (Just el, CBinary o a b)
        | isInt el
        , o `elem` [BAdd, BSub, BMul]
        , (readsRef r a && isConst b) || (readsRef r b && isConst a) ->
            [ Warning p ["overflow"] ["TC-OP-20", "NX-OP-32", "NX-ERR-24"] $
                refText names r <> " " <> binOpSymbol o <> " a constant, stored back in " <> refText names r <> ": after enough cycles or iterations it leaves " <> elemName el <> ", and then the overflow policy decides (saturate, wrap or a runtime error)"
            ]
      _ -> []

    -- a value stored into a narrower string or a subrange
    stored p t e = case (t, ceType e) of
      (TString _ cap, TString _ cap')
        | cap' > cap || not (isConst e) && producesString e ->
            [Warning p ["string-overflow"] ["TC-TYPE-27", "NX-TYPE-27"] ("a string of up to " <> T.pack (show (max cap cap')) <> " characters is stored into a STRING[" <> T.pack (show cap) <> "]: longer values are cut or a runtime error")]
      (TSubrange _ lo hi, _)
        | not (isConst e) ->
            [Warning p ["subrange"] ["TC-TYPE-33", "NX-ERR-17"] ("a value outside " <> T.pack (show lo) <> ".." <> T.pack (show hi) <> " stored here is a runtime error or stored unchecked")]
      _ -> []
    producesString e = case ceNode e of
      CStandard f _ -> key f `elem` ["CONCAT", "INSERT", "REPLACE"]
      _ -> False

    -- FOR: bounds written in the body, and a final value at the type's end
    forLoop p t end step body =
      let written = concatMap assigned body
          rereads = [x | x <- end : maybe [] pure step, any (`readsRef` x) written]
          atMax = case (baseElem t, ceNode end, step) of
            (Just el, CConst (VInt _ n), Nothing) | isInt el, n == snd (intRange el) -> True
            _ -> False
       in [ Warning (cePos x) ["for-bounds"] ["TC-STMT-26", "TC-STMT-27", "NX-STMT-25"] "the loop's body writes a variable of this bound: whether the bound is evaluated once or at every test decides how often the loop runs"
          | x <- rereads
          ]
            ++ [ Warning p ["for-at-type-max", "overflow"] ["TC-STMT-31", "NX-STMT-21"] ("the final value is the largest " <> maybe "" elemName (baseElem t) <> ": the control variable cannot pass it, so the loop ends only if the dialect stops at the type's end")
               | atMax
               ]

    -- expressions
    expr loops e = here ++ concatMap (expr loops) (children e)
      where
        here = case ceNode e of
          CBinary o a b
            | o `elem` [BDiv, BMod], Just el <- baseElem (ceType b), not (isConst b) ->
                [ if isAnyReal el
                    then Warning (cePos e) ["real-div-zero"] ["TC-OP-22", "NX-OP-29"] "a division by a REAL that can be 0: an infinity or a runtime error"
                    else
                      if o == BDiv
                        then Warning (cePos e) ["div-zero"] ["TC-OP-22", "NX-OP-29"] "a division by a value that can be 0: a runtime error or 0"
                        else Warning (cePos e) ["mod-zero"] ["TC-OP-24", "NX-DIFF-8"] "MOD by a value that can be 0: 0 or a runtime error"
                ]
                  ++ signedDivision o a b
            | o `elem` [BDiv, BMod] -> signedDivision o a b
            | o `elem` [BAnd, BOr], hasCall b ->
                [Warning (cePos b) ["short-circuit"] ["TC-OP-6", "NX-OP-22"] ("the right operand of " <> binOpSymbol o <> " calls a function: whether it runs when the left operand decides depends on short-circuit evaluation")]
          CConvert t a -> conversion (cePos e) (ceType a) t
          CStandard f [a] | isConversionName pol f -> conversion (cePos e) (ceType a) (ceType e)
          CRead r -> ref loops r
          _ -> []
    signedDivision o a b =
      [ Warning (cePos a) ["mod-sign"] ["TC-OP-21", "TC-OP-23", "NX-DIFF-8"] ("a negative operand of " <> binOpSymbol o <> ": the rounding of the quotient and the sign of the remainder depend on the dialect")
      | Just el <- [baseElem (ceType a)]
      , isSignedInt el
      , not (nonNegative a && nonNegative b)
      ]
    conversion p from to = case (baseElem from, baseElem to) of
      (Just x, Just y)
        | isAnyReal x, isInt y -> [Warning p ["real-to-int"] ["TC-CONV-12", "NX-CONV-23", "NX-CONV-24"] (elemName x <> " to " <> elemName y <> ": rounding or truncation, and values out of range, depend on the dialect")]
        | isInt x, isInt y, not (fitsIn x y) -> [Warning p ["narrow-int"] ["TC-CONV-13", "TC-CONV-14", "NX-ERR-23"] (elemName x <> " to " <> elemName y <> ": a value that does not fit wraps or saturates")]
      _ -> []
    fitsIn x y = let (lo, hi) = intRange x; (lo', hi') = intRange y in lo >= lo' && hi <= hi'

    -- an array index that is neither a constant nor a FOR loop's control variable
    ref loops = \case
      CIndex r ixs ->
        [ Warning (cePos ix) ["index-out-of-range"] ["TC-ERR-3", "NX-ERR-9"] "an index that can leave the array's bounds: a runtime error, or clamped to them"
        | ix <- ixs
        , not (isConst ix)
        , not (any (`isControl` ix) loops)
        ]
          ++ ref loops r
      CField r _ -> ref loops r
      CBit r _ -> ref loops r
      _ -> []
    isControl r ix = case ceNode ix of
      CRead r' -> sameRef r r'
      CConvert _ a -> isControl r a
      _ -> False

-- | The targets a statement (and those inside it) writes.
assigned :: CStmt -> [CRef]
assigned = \case
  CAssign _ r _ _ -> [r]
  CFor _ r _ _ _ _ body -> r : concatMap assigned body
  CIf _ arms els -> concatMap (concatMap assigned . snd) arms ++ concatMap assigned els
  CCase _ _ arms els -> concatMap (concatMap assigned . snd) arms ++ concatMap assigned els
  CWhile _ _ body -> concatMap assigned body
  CRepeat _ body _ -> concatMap assigned body
  CChain _ _ targets -> [r | (_, r, _, _) <- targets]
  CCallFB _ c -> [r | (_, r, _) <- fcOutputs c] ++ map snd (fcInOuts c)
  _ -> []

children :: CExpr -> [CExpr]
children e = case ceNode e of
  CUnary _ a -> [a]
  CBinary _ a b -> [a, b]
  CConvert _ a -> [a]
  CStandard _ as -> as
  CCall _ ins _ _ -> map snd ins
  CMethod _ _ ins _ _ -> map snd ins
  _ -> []

-- | Does the expression read the variable?
readsRef :: CRef -> CExpr -> Bool
readsRef r e = case ceNode e of
  CRead r' | sameRef r r' -> True
  _ -> any (readsRef r) (children e)

hasCall :: CExpr -> Bool
hasCall e = case ceNode e of
  CCall {} -> True
  CMethod {} -> True
  _ -> any hasCall (children e)

isConst :: CExpr -> Bool
isConst e = case ceNode e of
  CConst _ -> True
  CConvert _ a -> isConst a
  _ -> False

nonNegative :: CExpr -> Bool
nonNegative e = case ceNode e of
  CConst (VInt _ n) -> n >= 0
  CConvert _ a -> nonNegative a
  _ -> maybe False (not . isSignedInt) (baseElem (ceType e))

-- | The same variable, for the references the analysis compares.
sameRef :: CRef -> CRef -> Bool
sameRef a b = case (refPathText a, refPathText b) of
  (Just x, Just y) -> x == y
  _ -> False

refPathText :: CRef -> Maybe Text
refPathText = \case
  CLocal k -> Just ("L." <> k)
  CGlobal k -> Just ("G." <> k)
  CField r f -> (<> ("." <> f)) <$> refPathText r
  CInstance k -> Just ("I." <> k)
  CIndex r ixs -> (\t -> t <> "[" <> T.intercalate "," (mapMaybe constText ixs) <> "]") <$> refPathText r
  _ -> Nothing
  where
    constText ix = case ceNode ix of
      CConst v -> Just (renderValue v)
      CRead r -> refPathText r
      _ -> Nothing

-- | A variable as the program spells it.
refText :: Map Text Text -> CRef -> Text
refText names r = maybe "the variable" (T.intercalate "." . map (\k -> M.findWithDefault k k names) . T.splitOn "." . T.drop 2) (refPathText r)
