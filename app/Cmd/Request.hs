-- | @stref request CASE.st@: the stref-engine/1 request that
-- @stref conformance@ sends to an engine for one case, on one line, so that
-- a case can be looked at or fed to an engine by hand
-- (@stref request case.st | stref engine@). Exit 1 when the case file is
-- malformed, 2 on a usage error.
module Cmd.Request (Cmd.Request.command) where

import Cmd.PolicyOptions
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Options.Applicative hiding (command)
import qualified Options.Applicative
import Stref.Conformance.Case (effectiveExpect)
import Stref.Conformance.Corpus
import Stref.Conformance.Protocol (encodeRequest)
import Stref.Conformance.Runner
import System.Directory (doesDirectoryExist, doesFileExist)
import System.Exit
import System.IO (stderr)

data Opts = Opts
  { oCase :: FilePath
  , oPreset :: Maybe Text
  , oPolicies :: [(Text, Text)]
  }

command :: Mod CommandFields (IO ExitCode)
command =
  Options.Applicative.command
    "request"
    ( info
        (run <$> opts)
        (progDesc "Print, on one line, the stref-engine/1 request that `stref conformance` sends for a case")
    )
  where
    opts =
      Opts
        <$> strArgument (metavar "CASE.st" <> help "One case file of a corpus (a RULES index in a directory above it)")
        <*> optional presetChoice
        <*> policyAssignmentOption

complain :: Text -> IO ()
complain msg = TIO.hPutStrLn stderr ("stref request: " <> msg)

run :: Opts -> IO ExitCode
run o = case resolvePolicies (maybe "mastertool-xe" id (oPreset o)) (oPolicies o) of
  Left e -> complain e >> pure (ExitFailure 2)
  Right policies -> do
    isFile <- doesFileExist (oCase o)
    isDir <- doesDirectoryExist (oCase o)
    if isDir
      then complain (T.pack (oCase o) <> " is a directory; give one case file") >> pure (ExitFailure 2)
      else if not isFile
        then complain ("no such file: " <> T.pack (oCase o)) >> pure (ExitFailure 2)
        else do
          corpus <- loadCorpus [oCase o]
          mapM_ complain (corpusErrors corpus)
          -- the same choice of policies as `stref conformance`
          let options =
                defaultRunOptions
                  { roPolicies = policies
                  , roOverrides = maybe (Just (oPolicies o)) (const Nothing) (oPreset o)
                  }
          case corpusEntries corpus of
            [Loaded c] -> case casePolicies options c of
              Left e -> complain e >> pure (ExitFailure 2)
              Right pol -> do
                BLC.putStrLn (encodeRequest (buildRequest pol c (effectiveExpect pol c)))
                pure ExitSuccess
            [Invalid _ _ e] -> TIO.hPutStrLn stderr e >> pure (ExitFailure 1)
            _ -> complain ("cannot read a case from " <> T.pack (oCase o)) >> pure (ExitFailure 2)
